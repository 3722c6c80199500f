"""Command line: ``/usr/bin/python3 -m metamaterial_wb <command> ...``.

Sub-commands live in ``metamaterial_wb/commands/``: every module there that defines ``NAME``,
``HELP``, ``add_arguments(parser)`` and ``run(args) -> int`` is a sub-command, so a new command is a
new file and nothing else changes.

Errors: a :class:`~metamaterial_wb.core.errors.MetamaterialError` (bad input) prints one line on
stderr and exits with status 2; no output file is left behind (commands write atomically).
"""
import argparse
import importlib
import pkgutil
import sys

from metamaterial_wb import __version__
from metamaterial_wb.core.errors import MetamaterialError


def _command_modules():
    from metamaterial_wb import commands

    mods = []
    for info in sorted(pkgutil.iter_modules(commands.__path__), key=lambda m: m.name):
        if info.name.startswith("_"):
            continue
        mod = importlib.import_module(f"metamaterial_wb.commands.{info.name}")
        if all(hasattr(mod, a) for a in ("NAME", "HELP", "add_arguments", "run")):
            mods.append(mod)
    return mods


def build_parser():
    parser = argparse.ArgumentParser(
        prog="python3 -m metamaterial_wb",
        description="Sparsely actuated modular metamaterials: design, simulate, fabricate, drive.")
    parser.add_argument("--version", action="version", version=f"metamaterial_wb {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    for mod in _command_modules():
        p = sub.add_parser(mod.NAME, help=mod.HELP, description=mod.HELP)
        mod.add_arguments(p)
        p.set_defaults(_run=mod.run)
    return parser


def main(argv=None):
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args._run(args) or 0)
    except MetamaterialError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    except FileNotFoundError as exc:
        print(f"error: file not found: {exc.filename}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
