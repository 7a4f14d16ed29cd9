"""The exit-status contract of the ``epistemica`` command, and the guard that keeps it.

====  =================================================================================
0     success: every claim as expected, a ``--formula`` answered, a plan was found, ...
1     an answer of "no": a claim (or ``--formula --expect``) is false, no plan exists, ...
2     bad input: a malformed spec, an unknown name, a bad option, an unreadable file
3     an internal error, that is a bug in epistemica (``--debug`` shows the traceback)
130   interrupted (Ctrl-C)
====  =================================================================================

No traceback is printed without ``--debug``: a user error is printed as
``FILE:LINE:COL: error: ...`` with a hint, a bug as one line saying where to report it.
"""

from __future__ import annotations

import argparse
import sys
import traceback
from collections.abc import Callable

from epistemica.del_.errors import EpistemicaError

__all__ = [
    "EXIT_BUG",
    "EXIT_FALSE",
    "EXIT_INTERRUPTED",
    "EXIT_OK",
    "EXIT_USAGE",
    "REPORT_TO",
    "guarded",
]

EXIT_OK, EXIT_FALSE, EXIT_USAGE, EXIT_BUG, EXIT_INTERRUPTED = 0, 1, 2, 3, 130

# No project URL is published yet; the tracker is named rather than guessed.
REPORT_TO = "the epistemica issue tracker"


def guarded(handler: Callable[[argparse.Namespace], int], args: argparse.Namespace) -> int:
    """Run a command's ``handler`` and map whatever it raises onto the exit contract.

    ``args.debug`` (``--debug``) adds the traceback to every error report.
    """

    debug = bool(getattr(args, "debug", False))
    try:
        return int(handler(args))
    except KeyboardInterrupt:
        _traceback(debug)
        print("epistemica: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except BrokenPipeError:
        # The reader went away (`epistemica show ... | head`): nothing left to say to it.
        _silence_stdout()
        return EXIT_OK
    except EpistemicaError as err:
        _traceback(debug)
        print(err, file=sys.stderr)
        return EXIT_USAGE
    except OSError as err:  # a file that cannot be read or written: the user's to fix
        _traceback(debug)
        print(f"epistemica: error: {err}", file=sys.stderr)
        return EXIT_USAGE
    except Exception as err:  # anything else is a bug; so is RecursionError, MemoryError
        _traceback(debug)
        print(bug_message(err, debug), file=sys.stderr)
        return EXIT_BUG


def bug_message(err: BaseException, debug: bool = False) -> str:
    """The one line printed for an internal error.

    Examples
    --------
    >>> line = bug_message(ZeroDivisionError("division by zero"))
    >>> line.splitlines() == [line], "ZeroDivisionError: division by zero" in line
    (True, True)
    >>> "this is a bug in epistemica" in line, "--debug shows the traceback" in line
    (True, True)
    """
    what = f"{type(err).__name__}: {err}" if str(err) else type(err).__name__
    what = what.splitlines()[0] if what else what
    tail = "the traceback is above" if debug else "--debug shows the traceback"
    return (
        f"epistemica: internal error ({what}); this is a bug in epistemica, please report "
        f"it on {REPORT_TO} with the command you ran ({tail})"
    )


def _traceback(debug: bool) -> None:
    if debug:
        traceback.print_exc(file=sys.stderr)


def _silence_stdout() -> None:
    # Python flushes stdout again at exit, which would raise once more; point it at
    # /dev/null (the recipe of the Python documentation on SIGPIPE).
    import os

    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError):  # no real file descriptor (e.g. captured in tests)
        pass
