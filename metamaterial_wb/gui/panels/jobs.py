"""Long work off the GUI thread, with a progress bar, a Cancel button and a summary in the panel.

Two kinds of job share one :class:`JobBox` widget, one job at a time: while one runs, ``start`` of another job
of the same box returns False (the panel says why); the bar and Cancel belong to the running job.

* :class:`ThreadJob` runs pure-Python / numpy work (the dynamics simulation, the sleeve prediction) in a
  daemon thread. The work gets a ``report(fraction, text)`` callable; once Cancel is pressed,
  ``report`` raises :class:`Cancelled`, so the work stops at its next report, and its result is dropped.
* :class:`ProcessJob` runs work that builds B-rep and writes files (Export) in a child Python process:
  OpenCASCADE does not release the GIL and FreeCAD documents must not be made off the GUI thread, so a
  thread would still freeze the GUI. Cancel kills the process; its stderr lines are the progress text.

The panel polls nothing itself: a QTimer (ThreadJob) or QProcess signals (ProcessJob) call
``on_done(result)`` / ``on_error(message)`` / ``on_cancel()`` in the GUI thread.
"""
import json
import os
import shutil
import sys
import threading
import time

from PySide import QtCore, QtGui

import metamaterial_wb
from metamaterial_wb.gui.i18n import translate


class Cancelled(Exception):
    """Raised inside the work by ``report()`` once the user pressed Cancel."""


class JobBox(QtGui.QWidget):
    """Progress bar + status text + Cancel; hidden while no job runs. ``summary`` keeps the last result.
    ``job`` is the job that last started on it; one runs at a time (:meth:`busy_for`)."""

    def __init__(self, parent=None):
        super().__init__(parent)
        self.job = None
        lay = QtGui.QVBoxLayout(self)
        lay.setContentsMargins(0, 0, 0, 0)
        row = QtGui.QHBoxLayout()
        self.progress = QtGui.QProgressBar()
        self.progress.setRange(0, 1000)
        self.cancel_btn = QtGui.QPushButton(translate("Metamaterial", "Cancel"))
        self.cancel_btn.setToolTip(translate("Metamaterial", "Stop this job; nothing it would have written is kept"))
        row.addWidget(self.progress, 1)
        row.addWidget(self.cancel_btn)
        lay.addLayout(row)
        self.status = QtGui.QLabel("")
        self.status.setWordWrap(True)
        lay.addWidget(self.status)
        self.summary = QtGui.QLabel("")
        self.summary.setWordWrap(True)
        self.summary.setTextInteractionFlags(QtCore.Qt.TextInteractionFlag.TextSelectableByMouse)
        lay.addWidget(self.summary)
        self.set_running(False)

    def busy_for(self, job):
        """True while another job than ``job`` runs on this box (``job`` may not start then)."""
        other = self.job
        return other is not None and other is not job and other.running

    def set_running(self, on):
        self.progress.setVisible(on)
        self.cancel_btn.setVisible(on)
        self.status.setVisible(on)

    def set_progress(self, fraction=None, text=None):
        if fraction is None:
            self.progress.setRange(0, 0)            # busy indicator
        else:
            self.progress.setRange(0, 1000)
            self.progress.setValue(int(1000 * min(1.0, max(0.0, fraction))))
        if text is not None:
            self.status.setText(text)


class _Job:
    def __init__(self, box, on_done, on_error=None, on_cancel=None):
        self.box = box
        self.on_done, self.on_error, self.on_cancel = on_done, on_error, on_cancel
        self.running = False
        self.cancelled = False
        self.outcome = None        # "done" | "error" | "cancelled"
        self.started = None
        if box is not None:
            box.cancel_btn.clicked.connect(self.cancel)

    def _begin(self, text):
        self.running, self.cancelled, self.outcome = True, False, None
        self.started = time.perf_counter()
        if self.box is not None:
            self.box.job = self
            self.box.summary.setText("")
            self.box.set_progress(0.0, text)
            self.box.set_running(True)

    def _end(self, outcome, payload=None):
        self.running = False
        self.outcome = outcome
        if self.box is not None and not self.box.busy_for(self):
            self.box.set_running(False)
        if outcome == "done":
            self.on_done(payload)
        elif outcome == "error":
            if self.on_error:
                self.on_error(payload)
        elif self.on_cancel:
            self.on_cancel()

    @property
    def elapsed(self):
        return 0.0 if self.started is None else time.perf_counter() - self.started

    def wait(self, timeout_s=120.0):
        """Process events until the job ended (tests, scripts). True when it ended in time."""
        end = time.perf_counter() + timeout_s
        while self.running and time.perf_counter() < end:
            QtGui.QApplication.processEvents(QtCore.QEventLoop.ProcessEventsFlag.AllEvents, 50)
            time.sleep(0.005)
        return not self.running


class ThreadJob(_Job):
    """``work(report)`` in a daemon thread; ``report(fraction, text=None)`` updates the bar."""

    def __init__(self, box, on_done, on_error=None, on_cancel=None, interval_ms=100):
        super().__init__(box, on_done, on_error, on_cancel)
        self.timer = QtCore.QTimer()
        self.timer.setInterval(interval_ms)
        self.timer.timeout.connect(self._poll)
        self._state = None

    def start(self, work, text=None):
        if self.running or (self.box is not None and self.box.busy_for(self)):
            return False
        if text is None:
            text = translate("Metamaterial", "working ...")
        state = {"fraction": 0.0, "text": text, "done": False, "result": None, "error": None}
        self._state = state

        def report(fraction, note=None):
            if self.cancelled or state is not self._state:
                raise Cancelled()
            state["fraction"] = float(fraction)
            if note is not None:
                state["text"] = str(note)

        def run():
            try:
                state["result"] = work(report)
            except Cancelled:
                state["error"] = Cancelled
            except Exception as exc:  # noqa: BLE001 - reported in the panel
                state["error"] = str(exc) or type(exc).__name__
            state["done"] = True

        self._begin(text)
        threading.Thread(target=run, daemon=True).start()
        self.timer.start()
        return True

    def cancel(self):
        if not self.running:      # the box's Cancel is connected to every job of the box: only the running one acts
            return
        self.cancelled = True
        self.timer.stop()
        self._state = None               # the thread's report() raises; its result is dropped
        self._end("cancelled")

    def _poll(self):
        state = self._state
        if state is None:
            self.timer.stop()
            return
        if self.box is not None:
            self.box.set_progress(state["fraction"], state["text"])
        if not state["done"]:
            return
        self.timer.stop()
        self._state = None
        if state["error"] is Cancelled:
            self._end("cancelled")
        elif state["error"]:
            self._end("error", state["error"])
        else:
            self._end("done", state["result"])

    def stop(self):
        """Drop a running job without callbacks (the panel closes)."""
        self.timer.stop()
        self._state = None
        self.running = False


def child_python():
    """The Python interpreter FreeCAD runs on (for child processes)."""
    exe = sys.executable or ""
    if os.path.basename(exe).lower().startswith("python") and os.path.exists(exe):
        return exe
    for cand in (os.path.join(sys.prefix, "bin", "python3"), os.path.join(sys.prefix, "python.exe"),
                 shutil.which("python3") or ""):
        if cand and os.path.exists(cand):
            return cand
    return "python3"


def child_environment():
    """PYTHONPATH for a child process: this checkout and FreeCAD's own library folder."""
    env = QtCore.QProcessEnvironment.systemEnvironment()
    paths = [os.path.dirname(os.path.dirname(os.path.abspath(metamaterial_wb.__file__)))]
    try:
        import FreeCAD
        lib = os.path.join(FreeCAD.getHomePath(), "lib")
        if os.path.isdir(lib):
            paths.append(lib)
    except Exception:  # pragma: no cover
        pass
    old = env.value("PYTHONPATH", "")
    env.insert("PYTHONPATH", os.pathsep.join(paths + ([old] if old else [])))
    return env


class ProcessJob(_Job):
    """``python -m MODULE ARGS`` in a child process. The last stdout line must be a JSON result; stderr
    lines are shown as progress text. A non-zero exit is an error whose message is the last stderr line."""

    def __init__(self, box, on_done, on_error=None, on_cancel=None):
        super().__init__(box, on_done, on_error, on_cancel)
        self.proc = None
        self._retired = None        # a process that failed to start, kept until its signal is over
        self.stdout = ""
        self.stderr_lines = []
        self._buf = ""

    def start(self, module, args, text=None):
        if self.running or (self.box is not None and self.box.busy_for(self)):
            return False
        if text is None:
            text = translate("Metamaterial", "working ...")
        self.stdout, self.stderr_lines, self._buf = "", [], ""
        proc = QtCore.QProcess()
        proc.setProcessEnvironment(child_environment())
        proc.readyReadStandardError.connect(self._stderr)
        proc.readyReadStandardOutput.connect(self._stdout)
        proc.finished.connect(self._finished)
        proc.errorOccurred.connect(self._failed)
        self.proc = proc
        self._begin(text)
        if self.box is not None:
            self.box.set_progress(None, text)
        proc.start(child_python(), ["-m", module] + [str(a) for a in args])
        return True

    def _stderr(self):
        if self.proc is None:
            return
        self._buf += bytes(self.proc.readAllStandardError()).decode("utf-8", "replace")
        *lines, self._buf = self._buf.split("\n")
        lines = [ln.strip() for ln in lines if ln.strip()]
        self.stderr_lines += lines
        if lines and self.box is not None:
            self.box.set_progress(None, lines[-1])

    def _stdout(self):
        if self.proc is not None:
            self.stdout += bytes(self.proc.readAllStandardOutput()).decode("utf-8", "replace")

    def _finished(self, code, _status=None):
        if self.proc is None:
            return
        self._stdout()
        self._stderr()
        self.proc = None
        if self.cancelled:
            return
        last = [ln for ln in self.stdout.splitlines() if ln.strip()]
        if code == 0 and last:
            try:
                self._end("done", json.loads(last[-1]))
                return
            except ValueError:
                pass
        errs = [ln for ln in self.stderr_lines if ln.startswith("error:")] or self.stderr_lines or \
            [translate("Metamaterial", "the export process ended with status {0}").format(code)]
        self._end("error", errs[-1][6:].strip() if errs[-1].startswith("error:") else errs[-1])

    def _failed(self, err):
        if self.proc is not None and self.proc.state() == QtCore.QProcess.ProcessState.NotRunning and self.running \
                and not self.cancelled:
            # keep the QProcess alive until its own signal has returned (dropping the last reference here deleted
            # it under errorOccurred: a crash); a later start or failure lets it go
            self._retired, self.proc = self.proc, None
            self._end("error", translate("Metamaterial", "cannot start {0}: {1}").format(child_python(), err))

    def cancel(self):
        if not self.running:
            return
        self.cancelled = True
        proc, self.proc = self.proc, None
        if proc is not None:
            proc.kill()
            proc.waitForFinished(3000)
        self._end("cancelled")

    def stop(self):
        if self.running:
            self.cancelled = True
            proc, self.proc = self.proc, None
            if proc is not None:
                proc.kill()
                proc.waitForFinished(3000)
            self.running = False
