"""The link shared by several threads (the streaming thread and e.g. a GUI ping): replies land in
``Link.pending``, where every thread looks for its own seq. One thread's poll() went over the dict while
another popped its reply from it without the read lock: "RuntimeError: dictionary changed size during
iteration" (two threads PINGing one dry-run link with Python switching threads every 10 us hit it after
0.1 .. 20 s). Here ``pending`` also hands the GIL over between the items it yields, which makes a switch
in the middle of such a loop certain (the old code fails within a second); with every read-modify of
``pending`` under the lock nothing changes it while it is read."""
import sys
import threading
import time
import traceback

import pytest

serial = pytest.importorskip("serial")

from metamaterial_wb.hardware import protocol as P  # noqa: E402
from metamaterial_wb.hardware.link import Link  # noqa: E402

SWITCH_INTERVAL_S = 1e-5
RUN_S = 4.0


class SwitchingDict(dict):
    """A dict whose iteration gives other threads the GIL between items (a thread switch at the worst time)."""

    def __iter__(self):
        for k in dict.__iter__(self):
            time.sleep(0.0002)
            yield k


@pytest.fixture
def fast_switching():
    old = sys.getswitchinterval()
    sys.setswitchinterval(SWITCH_INTERVAL_S)
    try:
        yield
    finally:
        sys.setswitchinterval(old)


def test_two_threads_requesting_on_one_link(fast_switching):
    link = Link.open("", dry_run=True)
    try:
        link.handshake()
        link.pending = SwitchingDict(link.pending)
        errors, counts, sent = [], [0, 0], [0, 0]

        def worker(i):
            end = time.perf_counter() + RUN_S
            while time.perf_counter() < end and not errors:
                try:
                    sent[i] += 1
                    r = link.request(P.PING)
                    assert r.kind == "ACK" and r.request == P.PING, r
                    counts[i] += 1
                except BaseException:  # noqa: BLE001 - reported by the test below
                    errors.append(traceback.format_exc())
                    return

        threads = [threading.Thread(target=worker, args=(i,), daemon=True) for i in range(2)]
        for t in threads:
            t.start()
        for t in threads:
            t.join(RUN_S + 30)
        assert not any(t.is_alive() for t in threads), "a requesting thread hangs"
        assert not errors, errors[0][-2000:]
        assert counts == sent and all(c > 0 for c in counts), f"answered {counts} of {sent} requests"
        assert not link.pending, f"replies nobody claimed: {sorted(link.pending)}"
    finally:
        link.close()
