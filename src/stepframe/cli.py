"""The ``stepframe`` command: a thin layer over the library.

Conventions (DESIGN.md, Command line): every command takes ``--json`` and then prints only JSON on
stdout; a user error prints one line on stderr, ``stepframe: error: <file:line: >what, expected
what``, nothing on stdout, and exits 2 (``--debug`` shows the traceback); a warning is one line,
``stepframe: warning: ...``, and the command goes on. Sub-command groups live in
:mod:`stepframe.commands` (one module per group) and import the heavy libraries only when run, so
``stepframe --help`` starts fast.
"""

from __future__ import annotations

import argparse
import functools
import json
import sys
import traceback
import warnings
from collections.abc import Sequence
from typing import TextIO

from stepframe import __version__
from stepframe.commands import GROUPS, CommandResult, Parser, UserError, execute, group_module
from stepframe.core.jsonable import to_jsonable
from stepframe.core.text import terminal_safe
from stepframe.errors import InputError
from stepframe.pipeline.engine.integrity import StorageError
from stepframe.pipeline.engine.lock import WorkspaceBusy

EXAMPLES = """\
examples:
  stepframe demo                              select records for Example 4's frame, confirm
  stepframe demo --json                       the same as JSON
  stepframe records info RSN8883_14383980_13849360.AT2   peaks, durations, units
  stepframe structure frame-template > f.toml a commented frame file to edit
  stepframe <group> --help                    the commands of a group
"""


@functools.cache
def build_parser() -> argparse.ArgumentParser:
    """The whole command tree (no heavy imports), built once per process: 20 ms that a process
    calling :func:`main` many times (the test suite's in-process runs over a corpus of files)
    would otherwise pay per call. Parsing does not change it (argparse copies a list default
    before appending to it); it binds each command's function when built, so a test that
    patches one calls ``build_parser.cache_clear()`` after the patch and after the test."""
    parser = Parser(
        prog="stepframe",
        description="Seismic analysis of stepping (rocking) frames under earthquake ground motion.",
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--version", action="version", version=f"stepframe {__version__}")
    parser.add_argument("--json", action="store_true", help="print only JSON on stdout")
    parser.add_argument("--debug", action="store_true", help="show the traceback of an error")
    groups = parser.add_subparsers(dest="command", metavar="COMMAND")
    from stepframe.commands import run, select

    run.register(groups)
    select.register(groups)
    for name, helptext in GROUPS.items():
        group = groups.add_parser(
            name,
            help=helptext,
            description=helptext,
            formatter_class=argparse.RawDescriptionHelpFormatter,
        )
        sub = group.add_subparsers(dest="subcommand", metavar="SUBCOMMAND")
        group_module(name).register(sub)
        group.set_defaults(_group_parser=group)
    return parser


def _print_result(result: CommandResult, as_json: bool) -> None:
    if as_json:
        print(json.dumps(to_jsonable(result.data), indent=2, allow_nan=False))
    elif result.text:
        print(terminal_safe(result.text))


def _one_line_warning(
    message: Warning | str,
    category: type[Warning],
    filename: str,
    lineno: int,
    file: TextIO | None = None,
    line: str | None = None,
) -> None:
    """Show a warning (a skipped channel, a degraded result) as one line, like errors."""
    text = terminal_safe(str(message).replace("\n", " "))
    print(f"stepframe: warning: {text}", file=sys.stderr if file is None else file)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit status (0 done, 1 an output could not be produced
    or a file could not be written, 2 user error, 3 another run holds the workspace, 130
    interrupted)."""
    args_list = list(sys.argv[1:] if argv is None else argv)
    debug = "--debug" in args_list
    with warnings.catch_warnings():
        if not debug:
            warnings.showwarning = _one_line_warning
        return _run(args_list, debug)


def _parse(args_list: list[str]) -> argparse.Namespace:
    """The command line parsed; words no option takes are an error, which names the option that
    reads a TOML file when a stray word is one (``structure design pier.toml``: ``--input``)."""
    parser = build_parser()
    args, extras = parser.parse_known_args(args_list)
    if extras:
        hint = ""
        leaf = getattr(args, "_leaf_parser", None)
        if leaf is not None and any(word.lower().endswith(".toml") for word in extras):
            takers = [
                f"{action.option_strings[-1]} {action.metavar}"
                for action in leaf._actions
                if action.option_strings
                and isinstance(action.metavar, str)
                and action.metavar.upper().endswith("TOML")
            ]
            if takers:
                hint = f" (a TOML file is given with {' or '.join(takers)})"
        parser.error(f"unrecognized arguments: {' '.join(extras)}{hint}")
    return args


def _run(args_list: list[str], debug: bool) -> int:
    try:
        args = _parse(args_list)
        if getattr(args, "run", None) is None:
            # A group without a sub-command (or no command at all): show its help.
            target = getattr(args, "_group_parser", None) or build_parser()
            target.print_help()
            return 0 if not args_list else 2
        result = execute(args)
        _print_result(result, bool(args.json))
        return result.exit_code
    except WorkspaceBusy as busy:
        print(f"stepframe: error: {terminal_safe(str(busy))}", file=sys.stderr)
        return 3
    except StorageError as error:  # disk full, read-only: not the user's input; nothing half-done
        if debug:
            traceback.print_exc()
        print(f"stepframe: error: {terminal_safe(str(error))}", file=sys.stderr)
        return 1
    except (UserError, InputError) as error:
        if debug:
            traceback.print_exc()
        message = error.one_line() if isinstance(error, InputError) else str(error)
        print(f"stepframe: error: {terminal_safe(message)}", file=sys.stderr)
        return 2
    except (FileNotFoundError, IsADirectoryError, PermissionError) as error:
        if debug:
            traceback.print_exc()
        where = terminal_safe(str(error.filename))
        print(f"stepframe: error: {where}: {error.strerror}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("stepframe: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        return _broken_pipe()
    except OSError as error:
        # The machine, not the input: a full disk (ENOSPC, EDQUOT), a read-only file system, a
        # path of the wrong kind where a run writes. Writes go through temporary files, so
        # nothing is half-written; the run stops with one line and exit 1.
        if debug:
            traceback.print_exc()
        print(f"stepframe: error: {_os_error_line(error)}", file=sys.stderr)
        return 1
    except SystemExit as exit_:  # --help and --version exit through argparse
        return int(exit_.code or 0) if isinstance(exit_.code, int) else 0


def _broken_pipe() -> int:
    """The reader went away (``stepframe ... | head -1``): stop quietly, as ``yes | head``
    does. Point stdout at /dev/null so the interpreter's final flush does not fail again."""
    import os

    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, sys.stdout.fileno())
    return 141  # 128 + SIGPIPE, the shell's status for a command ended by a closed pipe


def _os_error_line(error: OSError) -> str:
    """One line for an error of the machine: the path, what the system said, what to do."""
    import errno

    where = " -> ".join(
        terminal_safe(str(name)) for name in (error.filename, error.filename2) if name is not None
    )
    said = error.strerror or type(error).__name__
    advice = {
        errno.ENOSPC: "expected room on the disk: free some and run again",
        errno.EDQUOT: "expected room in the disk quota: free some and run again",
        errno.EROFS: "expected a writable file system",
        errno.EEXIST: "expected a folder there, not a file: move the file away",
        errno.ENOTDIR: "expected a folder there, not a file: move the file away",
    }.get(error.errno or 0, "expected a usable file system")
    return f"{where + ': ' if where else ''}{said}, {advice} (nothing was half-written)"


if __name__ == "__main__":
    sys.exit(main())
