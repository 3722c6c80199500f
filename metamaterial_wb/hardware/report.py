"""``stream --report FILE``, written while the stream runs: memory stays bounded however long it streams.

    report = StreamReport("stats.json", channels).open()   # a temporary beside stats.json
    streamer.on_frame, streamer.on_clamp = report.frame, report.clamp
    ... streamer.run(...) ...
    report.finish(summary)      # the summary after the frames, then the rename: stats.json appears whole
    # a stream that fails after frames went out: report.finish(summary marked failed), the frames sent so far kept
    # a failure before any frame: report.discard()  (the temporary is removed; an earlier stats.json stays)

The file is one JSON object (``"format": "metamaterial-stream-report"``, ``"version": 1``), as it was when it was
built in memory and written at the end: ``frames_sent_columns``, then ``frames_sent`` (one line per tick, written
as the frames go out), then the statistics. Until :meth:`StreamReport.finish` it is a temporary file
``.tmp-<pid>-...-stats.json`` in the report's folder (core/fileio.py: a ``kill -9`` leaves it, the next write in
that folder sweeps it); the report's own path is never half written. A write that fails (a full disk) is kept in
:attr:`StreamReport.error`, the temporary removed, and ``on_error`` called once (the CLI stops the stream).
"""
import errno
import json
import os
import tempfile

from metamaterial_wb.core.fileio import sweep_stale, temp_prefix, write_target
from metamaterial_wb.core.outdir import missing_dirs, remove_new_dirs

FORMAT = "metamaterial-stream-report"
VERSION = 1
BUFFER_BYTES = 64 * 1024   # the frames held before they go to the file (about 1 200 ticks of two channels)


class StreamReport:
    def __init__(self, path, channels, option="--report"):
        self.shown = os.fspath(path)            # the path as the user gave it (error messages)
        self.path = write_target(os.path.abspath(self.shown), option)   # a link is written through
        self._by_ch = {c.name: c.channel for c in channels}
        self._columns = {str(c.channel): c.name for c in channels}
        self._f = None
        self._tmp = None
        self._made = []          # the folders open() created (removed again by discard())
        self._t = None           # the tick being gathered (one frame per run of adjacent channels)
        self._angles = {}
        self._wanted = {}
        self.frames_written = 0  # frames_sent entries written (ticks)
        self.error = None        # the OSError that stopped the writing, naming the report
        self.on_error = None     # callback(OSError), once, from the thread that wrote

    # ------------------------------------------------------------------------------------------
    def open(self):
        """Create the temporary file and write the head; an OSError naming the report if that fails."""
        folder = os.path.dirname(self.path)
        try:
            self._made = missing_dirs(folder)
            os.makedirs(folder, exist_ok=True)
            sweep_stale(folder)
            fd, self._tmp = tempfile.mkstemp(dir=folder, prefix=temp_prefix(),
                                             suffix="-" + os.path.basename(self.path)[-40:])
            self._f = os.fdopen(fd, "w", encoding="utf-8", buffering=BUFFER_BYTES)
        except OSError as exc:
            self.discard()
            raise self._named(exc) from exc
        self._write(f'{{"format": {json.dumps(FORMAT)}, "version": {VERSION},\n'
                    f' "frames_sent_columns": {json.dumps(self._columns)},\n "frames_sent": [')
        if self.error is not None:
            raise self.error
        return self

    def clamp(self, t, wanted):
        """Streamer.on_clamp: the motion's angles of the channels the host clamped in the frame at ``t``."""
        self._at(t)
        self._wanted.update(wanted)

    def frame(self, t, angles):
        """Streamer.on_frame: the angles one frame sent at ``t`` (a tick's frames are gathered into one entry)."""
        self._at(t)
        self._angles.update(angles)

    def finish(self, summary):
        """Write the last tick, ``summary`` (the statistics: a dict of JSON values) and the end, then rename the
        temporary onto the report. Raises (the temporary removed, nothing at the report's path replaced): an
        OSError naming the report, or ValueError / TypeError for a summary that is not JSON."""
        try:
            tail = json.dumps(summary, indent=1, allow_nan=False)   # before anything more is written
            self._flush()
            self._write(("\n ]" if self.frames_written else "]") + ("," + tail[1:] if summary else "\n}") + "\n")
            if self.error is not None:
                raise self.error
            f, self._f = self._f, None
            f.close()
            umask = os.umask(0)
            os.umask(umask)
            os.chmod(self._tmp, 0o666 & ~umask)  # mkstemp creates 0600; give the file normal permissions
            os.replace(self._tmp, self.path)
            self._tmp = None
        except OSError as exc:
            self.discard()
            if exc is self.error:
                raise
            raise self._named(exc) from exc
        except BaseException:
            self.discard()
            raise

    def discard(self):
        """Close and remove the temporary file and the folders ``open`` created, if empty (an earlier report at the
        path stays as it was); idempotent."""
        f, self._f = self._f, None
        if f is not None:
            try:
                f.close()
            except OSError:
                pass   # a full disk refusing the buffered rest: the file goes anyway
        tmp, self._tmp = self._tmp, None
        if tmp is not None and os.path.lexists(tmp):
            os.unlink(tmp)
        made, self._made = self._made, []
        remove_new_dirs(made)      # the folders open() created, if still empty

    # ------------------------------------------------------------------------------------------
    def _at(self, t):
        t = round(t, 9)
        if t != self._t:
            self._flush()
            self._t = t

    def _by_channel(self, angles):
        return {str(self._by_ch[n]): round(a, 4) + 0.0  # + 0.0: never -0.0
                for n, a in sorted(angles.items(), key=lambda kv: self._by_ch[kv[0]])}

    def _flush(self):
        """Write the tick gathered so far as one ``frames_sent`` entry (angles_deg: what each channel was sent;
        wanted_deg, only where the host clamped: the motion's angle)."""
        if self._angles:
            entry = {"t": self._t, "angles_deg": self._by_channel(self._angles)}
            if self._wanted:
                entry["wanted_deg"] = self._by_channel(self._wanted)
            self._write(("," if self.frames_written else "") + "\n  " + json.dumps(entry, allow_nan=False))
            self.frames_written += 1
        self._angles, self._wanted = {}, {}

    def _write(self, text):
        if self._f is None or self.error is not None:
            return
        try:
            self._f.write(text)
        except OSError as exc:
            self.error = self._named(exc)
            self.discard()
            if self.on_error:
                self.on_error(self.error)

    def _named(self, exc):
        """``exc`` as an OSError of the same errno naming the report as the user gave it (``f.write`` on a full
        disk names no file; the CLI prints the name an OSError carries)."""
        name = exc.filename
        if name is not None and name != self.path and not os.path.basename(os.fsdecode(name)).startswith(
                temp_prefix()):
            return exc      # another file's error (a folder on the way): as it is
        return OSError(exc.errno or errno.EIO, exc.strerror or str(exc), self.shown)
