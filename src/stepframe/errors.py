"""Exception types shared by every stage.

A user error (bad file, bad option, non-physical parameter) is an :class:`InputError`. Its message
is one line, ``<file>:<line>: <what was found>, expected <what>``, so that the command line can
print it as ``stepframe: error: ...`` and exit 2 without a traceback. Numerical failures that are
not the user's fault are reported as statuses by the functions that detect them, not raised.
"""

from __future__ import annotations

from os import PathLike


class StepframeError(Exception):
    """Base class of every error raised on purpose by stepframe."""


class InputError(StepframeError, ValueError):
    """Bad input given by the user: a file, an option, or a parameter value.

    Parameters
    ----------
    what
        What was found wrong, and what was expected (``"DT missing, expected 'DT= <seconds>'"``).
    path
        The file the problem is in, if any.
    line
        The 1-based line number in ``path``, if known.
    key
        The option or file key the problem is in (``n_steps``), if it is one: a workflow
        reader uses it to point at the key's line.
    """

    def __init__(
        self,
        what: str,
        path: str | PathLike[str] | None = None,
        line: int | None = None,
        *,
        key: str | None = None,
    ) -> None:
        self.what = what
        self.path = None if path is None else str(path)
        self.line = line
        self.key = key
        super().__init__(self.one_line())

    def one_line(self) -> str:
        """The message as one line: ``file:line: what``."""
        where = ""
        if self.path is not None:
            where = self.path if self.line is None else f"{self.path}:{self.line}"
            where += ": "
        return (where + self.what).replace("\n", " ")


class FormatError(InputError):
    """A file that claims (or was told) to be in a format but does not follow it."""
