"""The memory budget: what one run may hold at once, checked from its inputs before it starts.

Every command estimates its peak memory from its inputs (a record's samples times the arrays its
work holds, frequencies times time steps, replicates times their size) and refuses, with one
line, what would pass the budget, before anything is allocated: a request too large for the
machine is a user's error (exit 2) that says what it would need, never a machine that swaps
or a process the kernel kills.

The budget is :data:`DEFAULT_FRACTION` of the memory this process may use: the machine's
physical memory, or a container's limit (cgroup v2 ``memory.max``, v1
``memory.limit_in_bytes``) when it is lower; under an address-space limit (``ulimit -v``,
``RLIMIT_AS``) it is at most :data:`ADDRESS_SPACE_FRACTION` of what that limit leaves above
the address space already mapped (the interpreter's libraries map far more than they touch, so
the limit, not the machine, is what a large allocation meets first). ``--memory-mb MB`` (every
command, :class:`MemoryOptions`) sets it, through the environment variable :data:`ENVIRONMENT`,
which the worker processes of a run inherit; a library user sets it with :func:`set_budget_mb`
(or the variable). Standard library only: the command line reads :class:`MemoryOptions` for its
help.
"""

from __future__ import annotations

import contextlib
import math
import os
from collections.abc import Iterator
from dataclasses import dataclass

from stepframe.core.options import Range, check_fields, option

#: The environment variable that holds the budget [MiB] (set by ``--memory-mb``).
ENVIRONMENT = "STEPFRAME_MEMORY_MB"
#: Share of the machine's (or container's) memory one run may use by default: the rest is the
#: operating system's, the page cache's and other programs'.
DEFAULT_FRACTION = 0.5
#: Share of an address-space limit's room (the limit less what is mapped already) one run may
#: use: numpy's temporaries and the allocator's slack are mapped beside what the estimate counts.
ADDRESS_SPACE_FRACTION = 0.5
#: Budget when the machine's memory cannot be read [bytes] (4 GiB).
FALLBACK_BYTES = 4 * 1024**3
#: Smallest and largest budget a user may set [MiB] (the interpreter and its libraries alone
#: take about 100 MiB; 10⁹ MiB is past any machine).
MIN_MB, MAX_MB = 64.0, 1e9

_MIB = 1024**2
_CGROUP_LIMITS = (
    "/sys/fs/cgroup/memory.max",
    "/sys/fs/cgroup/memory/memory.limit_in_bytes",
)


@dataclass(frozen=True)
class MemoryOptions:
    """The memory budget of a run (the ``--memory-mb`` option of every command)."""

    memory_mb: float | None = option(
        None,
        "memory this run may use [MiB]; work estimated to need more is refused before it "
        "starts (default: half the machine's memory; under ulimit -v at most half of what it "
        "leaves; also the variable STEPFRAME_MEMORY_MB)",
        kind="positive",
        metavar="MB",
        valid=Range(MIN_MB, MAX_MB),
    )

    def __post_init__(self) -> None:
        check_fields(self)

    @contextlib.contextmanager
    def applied(self) -> Iterator[None]:
        """:attr:`memory_mb` (when given) as the budget of this process and of the workers it
        starts, for the duration of the ``with`` block (a command run in-process leaves the
        budget as it found it)."""
        previous = os.environ.get(ENVIRONMENT)
        if self.memory_mb is not None:
            set_budget_mb(self.memory_mb)
        try:
            yield
        finally:
            if previous is None:
                os.environ.pop(ENVIRONMENT, None)
            else:
                os.environ[ENVIRONMENT] = previous


def machine_bytes() -> int | None:
    """The memory this process may use [bytes]: physical memory, or a lower container limit
    (None when neither can be read)."""
    found: list[int] = []
    with contextlib.suppress(ValueError, OSError, AttributeError):
        found.append(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))
    for path in _CGROUP_LIMITS:
        try:
            with open(path) as handle:
                text = handle.read().strip()
        except OSError:
            continue
        if text.isdigit():  # "max": no limit
            found.append(int(text))
    usable = [value for value in found if value > 0]
    return min(usable) if usable else None


def address_space_room() -> int | None:
    """What the address-space limit (``RLIMIT_AS``, ``ulimit -v``) leaves this process above
    the address space it has mapped now [bytes]; None without a limit (or where it cannot be
    read)."""
    try:
        import resource

        soft, _ = resource.getrlimit(resource.RLIMIT_AS)
    except (ImportError, OSError, ValueError, AttributeError):
        return None
    if soft == resource.RLIM_INFINITY or soft <= 0:
        return None
    mapped = 0
    with contextlib.suppress(OSError, ValueError, StopIteration):
        with open("/proc/self/status") as handle:
            line = next(x for x in handle if x.startswith("VmSize:"))
        mapped = int(line.split()[1]) * 1024
    return max(soft - mapped, 0)


def set_budget_mb(mb: float) -> None:
    """Set the budget of this process and of the workers it starts [MiB]."""
    MemoryOptions(memory_mb=mb)  # the one check of the option
    os.environ[ENVIRONMENT] = repr(float(mb))


def budget_bytes() -> float:
    """The budget [bytes]: :data:`ENVIRONMENT` when set, else :data:`DEFAULT_FRACTION` of
    :func:`machine_bytes`; either way at most :data:`ADDRESS_SPACE_FRACTION` of
    :func:`address_space_room` under an address-space limit."""
    return min(_given_or_machine(), _address_space_budget())


def _address_space_budget() -> float:
    room = address_space_room()
    return math.inf if room is None else ADDRESS_SPACE_FRACTION * room


def _given_or_machine() -> float:
    text = os.environ.get(ENVIRONMENT)
    if text:
        from stepframe.errors import InputError

        try:
            mb = float(text)
        except ValueError:
            mb = float("nan")
        if not Range(MIN_MB, MAX_MB).contains(mb):
            raise InputError(
                f"{ENVIRONMENT} = {text!r}, expected a memory budget in MiB "
                f"{Range(MIN_MB, MAX_MB).describe()}"
            )
        return mb * _MIB
    machine = machine_bytes()
    return DEFAULT_FRACTION * (FALLBACK_BYTES if machine is None else machine)


def _budget_source() -> str:
    """Where the budget came from, for the refusal."""
    if _address_space_budget() < _given_or_machine():
        return f"{ADDRESS_SPACE_FRACTION:.0%} of what the address-space limit (ulimit -v) leaves"
    if os.environ.get(ENVIRONMENT):
        return "--memory-mb"
    return f"{DEFAULT_FRACTION:.0%} of this machine's memory; --memory-mb MB sets it"


def size_text(n_bytes: float) -> str:
    """A size in words: ``3.1 GiB``, ``420 MiB``, ``12 KiB``, ``900 bytes``."""
    for unit, scale in (("TiB", 1024**4), ("GiB", 1024**3), ("MiB", 1024**2), ("KiB", 1024)):
        if n_bytes >= scale:
            value = n_bytes / scale
            return f"{value:.0f} {unit}" if value >= 100 else f"{value:.3g} {unit}"
    return f"{n_bytes:.0f} bytes"


def check_memory(
    need_bytes: float, what: str, advice: str = "", *, budget: float | None = None
) -> None:
    """Refuse work estimated to need more than the budget: the one place a refusal for memory
    is worded (:func:`refusal`).

    Parameters
    ----------
    need_bytes
        The estimate of the work's peak [bytes] (not finite counts as above any budget).
    what
        The work, as the user asked for it ("fitting 15000000 samples").
    advice
        What to change, for the message ("fewer frequencies").
    budget
        The budget [bytes] (default :func:`budget_bytes`).

    Raises
    ------
    InputError
        :func:`refusal`'s one line.
    """
    limit = budget_bytes() if budget is None else float(budget)
    if need_bytes <= limit:  # also False for NaN
        return
    from stepframe.errors import InputError

    source = _budget_source() if budget is None else "as given"
    raise InputError(refusal(need_bytes, what, limit, source, advice))


def refusal(need_bytes: float, what: str, budget: float, source: str, advice: str = "") -> str:
    """The one wording of a refusal for memory: ``<what> needs about <size> of memory, over
    the budget of <size> (<source>), expected work that fits it[: <advice>]``."""
    finite = math.isfinite(need_bytes) and need_bytes < 1e30
    need = size_text(need_bytes) if finite else "more memory than any machine has"
    return (
        f"{what} needs about {need} of memory, over the budget of {size_text(budget)} "
        f"({source}), expected work that fits it" + (f": {advice}" if advice else "")
    )


__all__ = [
    "ADDRESS_SPACE_FRACTION",
    "DEFAULT_FRACTION",
    "ENVIRONMENT",
    "MemoryOptions",
    "address_space_room",
    "budget_bytes",
    "check_memory",
    "machine_bytes",
    "refusal",
    "set_budget_mb",
    "size_text",
]
