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

# the fields of the command's input file (a scene, calibrate's test piece, the sleeve spec) checked after it was read,
# by the model that uses them: a hinge size outside the calibration table (``joints[1].length_mm (H0,0)``),
# ``dynamics.friction`` (the dynamics model), ``fabrication.*`` and ``modules[k].*`` (the build), ``ring`` (the
# sleeve's end pieces), ...: the loaders name the file in their own errors ("(in PATH)"), the objects keep no path,
# so main() adds it to an error whose field starts with a top-level field of that file (:func:`_in_scene_file`)
_FIELD_ROOT = re.compile(r"[A-Za-z_][A-Za-z0-9_]*(?=$|[.\[ ])")


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


def _input_file(args):
    """``(path, top-level fields)`` of the command's own input file (``args.scene``, calibrate's ``args.piece``, the
    sleeve command's ``args.spec``), or ``(None, ())``."""
    for attr in ("scene", "piece"):
        if isinstance(getattr(args, attr, None), str):
            from metamaterial_wb.core.scene.names import KNOWN_KEYS
            return getattr(args, attr), KNOWN_KEYS | {"dynamics", "fabrication"}
    if isinstance(getattr(args, "spec", None), str):
        from metamaterial_wb.core.sleeve.spec import FIELDS
        return args.spec, set(FIELDS[""])
    return None, ()


def _in_scene_file(exc, args):
    """``exc`` with `` (in FILE)`` added when it names a field of the command's input file (:func:`_input_file`)
    that is checked after loading (:data:`_FIELD_ROOT`), as the loaders' own errors end; any other error as it is:
    one that names the file already, or another input (``--channels FILE``, calibrate's ``ANGLES.csv:LINE``), or a
    flag."""
    path, roots = _input_file(args)
    if not (isinstance(exc, SceneError) and path and isinstance(exc.field, str)):
        return exc
    root = _FIELD_ROOT.match(exc.field)
    other = [v for k, v in vars(args).items() if isinstance(v, str) and v and not k.startswith("_")]
    if (root is None or root.group(0) not in roots or path in str(exc)
            or any(exc.field == v or exc.field.startswith((v + ":", v + " ")) for v in other)):
        return exc
    return SceneError(exc.field, f"{exc.message} (in {path})")


def _os_message(exc):
    """``FILE: REASON`` of an OSError (the writers of core/fileio.py name the file also where the system does not,
    e.g. a write that fills the disk), with what to do when the disk or the quota is full."""
    import errno

    where = f"{exc.filename}: " if exc.filename is not None else ""
    full = exc.errno in (errno.ENOSPC, getattr(errno, "EDQUOT", errno.ENOSPC))
    return (f"{where}{exc.strerror or exc}" + ("; free space there (or ask for a larger quota), or write to a folder "
                                              "on another disk, and run the command again" if full else ""))


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
        print(f"error: {_one_line(_os_message(exc))}", file=sys.stderr)
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
