"""A host slower than the frame period (its per-tick work, e.g. a busy GUI thread, takes longer than 1 / rate) is
not a board that stopped answering: the replies wait unread in the link's buffer while the stream has no time left
to collect them between deadlines, and Streamer.run reads them before it judges the silence (the silence bound,
Streamer.silence_limit_s, stopped such a healthy stream after 0.75 s: "the board stopped answering"). Over the dry
run's loop://, whose echo stands for the board's answers."""
import time

import pytest

pytest.importorskip("serial")

from metamaterial_wb.hardware.link import Link  # noqa: E402
from metamaterial_wb.hardware.mapping import ChannelConfig  # noqa: E402
from metamaterial_wb.hardware.streamer import Streamer  # noqa: E402


def test_a_host_slower_than_the_period_streams_to_its_end():
    link = Link.open("loop://", dry_run=True)
    s = Streamer(link, [ChannelConfig("m1", 0, scale_deg=90.0)], rate_hz=50)
    s._link_timing = (500, 500, 5000)   # (as prepare() sets them: a 500 ms link watchdog)

    def slow(t):
        time.sleep(0.021)               # the host's work per tick a little longer than the 20 ms period
        return {"m1": 0.1}

    stats = s.run(slow, duration_s=2.0)  # 2 s: well past the 0.75 s silence bound
    assert stats.frames > 40 and stats.last_t > 1.5
    assert stats.acked + 1 >= stats.frames, (stats.acked, stats.frames)   # all answered (the last may be in flight)
