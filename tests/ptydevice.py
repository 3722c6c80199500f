"""A scripted servolink device on the master side of a pseudo-terminal, for host tests without the emulator:
the pty, the reading thread and the frame parsing; a subclass answers each packet (``answer``) and may act
between reads (``tick``)."""
import os
import pty
import select
import threading
import tty

import pytest

from metamaterial_wb.hardware import protocol as P


class PtyDevice(threading.Thread):
    """``port`` is the slave side's path; every packet read is handed to :meth:`answer`, whose bytes (if any) are
    written back."""

    poll_s = 0.02

    def __init__(self):
        super().__init__(daemon=True)
        self.master, self.slave = pty.openpty()
        tty.setraw(self.slave)
        self.port = os.ttyname(self.slave)
        self.stop_flag = False

    def answer(self, pkt):
        """The bytes to write back for ``pkt`` (None: nothing)."""
        raise NotImplementedError

    def tick(self):
        """Called between reads (timed events)."""

    def run(self):
        rd = P.FrameReader()
        while not self.stop_flag:
            self.tick()
            r, _, _ = select.select([self.master], [], [], self.poll_s)
            if not r:
                continue
            try:
                data = os.read(self.master, 256)
            except OSError:
                return
            for pkt in rd.feed(data):
                out = self.answer(pkt)
                if out:
                    os.write(self.master, out)

    def close(self):
        self.stop_flag = True
        self.join(1)
        os.close(self.master)
        os.close(self.slave)


def device_fixture(cls):
    """A pytest fixture making started devices of ``cls`` (``device(**kw)``), closed after the test."""
    @pytest.fixture
    def device():
        devs = []

        def make(**kw):
            d = cls(**kw)
            d.start()
            devs.append(d)
            return d
        yield make
        for d in devs:
            d.close()
    return device
