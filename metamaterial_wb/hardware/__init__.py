"""Hardware layer of the Metamaterial Workbench: the servolink v1 serial protocol to the servo firmware
(``firmware/``), the actuator -> servo channel mapping, and 50 Hz streaming of a scene's motion.

Small API for the GUI and scripts (no FreeCAD, pyserial imported lazily)::

    from metamaterial_wb.hardware import Link, Streamer, channel_map
    link = Link.open(port)                      # "/dev/ttyUSB0", a simulator pty, or "loop://" (dry_run=True)
    streamer = Streamer(link, channel_map(scene))
    streamer.prepare()                          # handshake, channel config, watchdog, ARM
    streamer.start(scene)                       # or a callable t -> {actuator name: value}
    streamer.stop(disarm=False)                 # -> StreamStats
"""
from .link import Link, LinkError  # noqa: F401
from .mapping import ChannelConfig, channel_map, check_motion, parse_map  # noqa: F401
from .streamer import StreamStats, Streamer  # noqa: F401
