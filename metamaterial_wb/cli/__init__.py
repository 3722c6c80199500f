"""Command line: ``/usr/bin/python3 -m metamaterial_wb <command> ...``.

Sub-commands are the modules of this package (``metamaterial_wb/cli/``): every module here that defines
``NAME``, ``HELP``, ``add_arguments(parser)`` and ``run(args) -> int`` is a sub-command, so a new command
is a new file and nothing else changes. (FreeCAD's GUI commands are ``metamaterial_wb/gui/commands.py``.)

Errors: a :class:`~metamaterial_wb.core.errors.MetamaterialError` (bad input) prints one line on
stderr and exits with status 2; so do a file the system refuses (OSError), running out of memory and
nesting too deep for Python, and a command line argparse refuses (``error: MESSAGE (PROG --help)``, no usage
block). No output file is left behind (commands write atomically): SIGTERM and
SIGHUP are turned into KeyboardInterrupt so every ``finally`` removes its temporary files (exit
128 + signal number, 130 for Ctrl-C).
"""
import argparse
import importlib
import pkgutil
import re
import sys

from metamaterial_wb import __version__
from metamaterial_wb.core.errors import MetamaterialError, SceneError

# the scene fields checked after the scene was read, by the model that uses them: a hinge size outside the
# calibration table (core/calibration.py: ``hinge.length_mm``, ``joints[1].length_mm (H0,0)``); Scene.load names
# the file in its own errors ("(in PATH)"), the scene object keeps no path, so main() adds it to these
_LATE_SCENE_FIELD = re.compile(r"(hinge|joints\[[0-9]+\])\.")


def _command_modules():
    mods = []
    for info in sorted(pkgutil.iter_modules(__path__), key=lambda m: m.name):
        if info.name.startswith("_"):
            continue
        mod = importlib.import_module(f"{__name__}.{info.name}")
        if all(hasattr(mod, a) for a in ("NAME", "HELP", "add_arguments", "run")):
            mods.append(mod)
    return mods


def number(text):
    """argparse ``type=`` for a decimal number, read strictly (:func:`metamaterial_wb.core.numbers.parse_float`:
    no ``1_0``, no non-ASCII digits, no inf/nan, no subnormals); argparse names the flag in the error."""
    from metamaterial_wb.core.numbers import parse_float
    try:
        return parse_float("", text)
    except MetamaterialError as e:
        raise argparse.ArgumentTypeError(str(e)) from None


def integer(text):
    """argparse ``type=`` for a whole number, read strictly (:func:`metamaterial_wb.core.numbers.parse_int`)."""
    from metamaterial_wb.core.numbers import parse_int
    try:
        return parse_int("", text)
    except MetamaterialError as e:
        raise argparse.ArgumentTypeError(str(e)) from None


class _Parser(argparse.ArgumentParser):
    """An argparse parser whose errors are what every other error of the CLI is: one line ``error: MESSAGE
    (PROG --help)`` on stderr and exit status 2 (argparse printed its usage block first). ``--help`` is unchanged.
    An unknown flag is blamed on the command that was given (argparse's top-level parser reported it)."""

    commands = None          # the top-level parser: {command name: its parser}

    def error(self, message):
        self.exit(2, f"error: {_one_line(message)} ({self.prog} --help)\n")

    def parse_args(self, args=None, namespace=None):
        args, extra = self.parse_known_args(args, namespace)
        if extra:
            owner = (self.commands or {}).get(getattr(args, "command", None), self)
            owner.error("unrecognized arguments: " + " ".join(extra))
        return args


def build_parser():
    parser = _Parser(
        prog="python3 -m metamaterial_wb",
        description="Sparsely actuated modular metamaterials: design, simulate, fabricate, drive.")
    parser.add_argument("--version", action="version", version=f"metamaterial_wb {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True
    parser.commands = {}
    for mod in _command_modules():
        p = sub.add_parser(mod.NAME, help=mod.HELP, description=mod.HELP)
        mod.add_arguments(p)
        p.set_defaults(_run=mod.run)
        parser.commands[mod.NAME] = p
    return parser


class _Signalled(KeyboardInterrupt):
    def __init__(self, signum):
        super().__init__(signum)
        self.signum = signum


def _raise_signalled(signum, frame):
    raise _Signalled(signum)


def _install_signals():
    """SIGTERM / SIGHUP -> exception (so ``finally`` blocks clean up); returns the previous handlers."""
    import signal
    import threading

    if threading.current_thread() is not threading.main_thread():
        return {}
    old = {}
    for sig in (signal.SIGTERM, getattr(signal, "SIGHUP", None)):
        if sig is not None:
            old[sig] = signal.signal(sig, _raise_signalled)
    return old


def _one_line(text, limit=500):
    text = " ".join(str(text).split())
    return text if len(text) <= limit else text[:limit] + " ..."


def _in_scene_file(exc, args):
    """``exc`` with `` (in SCENE)`` added when it names a field of the command's scene file (``args.scene``, or
    calibrate's ``args.piece``) that is checked after loading (:data:`_LATE_SCENE_FIELD`), as the scene's own
    errors end; any other error as it is."""
    path = getattr(args, "scene", None) or getattr(args, "piece", None)
    if not (isinstance(exc, SceneError) and isinstance(path, str) and isinstance(exc.field, str)
            and _LATE_SCENE_FIELD.match(exc.field) and f"(in {path})" not in exc.message):
        return exc
    return SceneError(exc.field, f"{exc.message} (in {path})")


def main(argv=None):
    import signal

    parser = build_parser()
    args = parser.parse_args(argv)
    old = _install_signals()
    try:
        return int(args._run(args) or 0)
    except MetamaterialError as exc:
        print(f"error: {_one_line(_in_scene_file(exc, args))}", file=sys.stderr)
        return 2
    except OSError as exc:
        where = exc.filename if exc.filename is not None else ""
        print(f"error: {where}{': ' if where else ''}{exc.strerror or exc}", file=sys.stderr)
        return 2
    except MemoryError:
        print("error: out of memory; the scene is too large for this machine (docs/scene-format.md, size "
              "budget)", file=sys.stderr)
        return 2
    except RecursionError:
        print("error: too deeply nested for this program", file=sys.stderr)
        return 2
    except _Signalled as exc:
        print(f"terminated by signal {exc.signum}", file=sys.stderr)
        return 128 + exc.signum
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
    finally:
        for sig, h in old.items():
            signal.signal(sig, h)
