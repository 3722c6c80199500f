"""Stream controller: the motor values of the animation's wall-clock time to the servo firmware.

The :class:`~metamaterial_wb.hardware.Streamer` thread asks for values at 50 Hz; the controller answers
with ``values_at(clock())``: the values for *now* on the animation clock (which follows wall time), not
the last frame the view managed to draw, so real servos move in real time even when rendering drops
frames. Errors from the streaming thread are kept and reported by the panel in the GUI thread.
"""


def hardware_available():
    """True when the hardware package (serial link + streamer) can be imported."""
    try:
        from metamaterial_wb.hardware import Link, Streamer, channel_map  # noqa: F401
        return True
    except ImportError:
        return False


def servo_scales(scene):
    """``{actuator: degrees per unit value}`` (the servo mapping of hardware.mapping; 90 by default)."""
    try:
        from metamaterial_wb.hardware.mapping import channel_map
        return {c.name: float(c.scale_deg) for c in channel_map(scene)}
    except Exception:  # noqa: BLE001 - no actuators / no hardware package: the seed's -90..90 servos
        return {a.name: 90.0 for a in scene.actuators}


class StreamController:
    """Open / close the link and run the streamer. ``values_at(t)`` -> {actuator: value};
    ``clock()`` -> the animation time now."""

    def __init__(self, values_at, clock):
        self.values_at = values_at
        self.clock = clock
        self.link = None
        self.streamer = None
        self.error = None
        self.sent = 0

    @property
    def connected(self):
        return self.streamer is not None

    def source(self, _stream_t):
        vals = self.values_at(self.clock())
        self.sent += 1
        return vals

    def connect(self, port, scene):
        """Open ``port`` (``loop://`` = dry run), hand-shake, ARM and start streaming. Raises on failure
        (nothing left open)."""
        from metamaterial_wb.hardware import Link, Streamer, channel_map
        link = None
        try:
            link = Link.open(port, dry_run=port.startswith("loop://"))
            streamer = Streamer(link, channel_map(scene))
            streamer.prepare()
            streamer.on_error = self._failed
            streamer.start(self.source)
        except Exception:
            if link is not None:
                try:
                    link.close()
                except Exception:  # noqa: BLE001
                    pass
            raise
        self.link, self.streamer, self.error = link, streamer, None
        return streamer

    def _failed(self, message):       # called from the streaming thread
        self.error = message

    def take_error(self):
        err, self.error = self.error, None
        return err

    def disconnect(self):
        """Stop streaming (the firmware's watchdog holds, then parks the servos); returns the stats."""
        stats = None
        if self.streamer is not None:
            try:
                stats = self.streamer.stop(disarm=False)
            except Exception:  # noqa: BLE001
                pass
        if self.link is not None:
            try:
                self.link.close()
            except Exception:  # noqa: BLE001
                pass
        self.streamer = self.link = None
        return stats
