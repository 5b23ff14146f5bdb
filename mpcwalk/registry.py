"""One registry style for everything chosen by name: :class:`Registry` of :class:`Entry`.

Pattern generators, QP back-ends, stabilizers, named controllers and experiments are each
one :class:`Registry`: a name, a one-line summary, what the name stands for (loaded on
demand, so that naming a closed form does not import the QP back-ends), whether it runs on
this installation and, where it does not, how to install it. Every registry is filled by the
module that owns it, from a literal list of entries: nothing registers itself as a side
effect of being imported elsewhere. The command line lists each registry the same way
(``mpcwalk generators``, ``mpcwalk solvers``, ``mpcwalk stabilizers``, ``mpcwalk
controllers``, ``mpcwalk experiment list``).

A new entry of a registry is one :class:`Entry` in its owner's list, e.g.::

    Entry("mpc", "linear MPC (Wieber)", lambda: MpcGenerator)
"""

from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass
from typing import Generic, TypeVar

from mpcwalk.exceptions import NotRegistered

T = TypeVar("T")


def _always() -> bool:
    return True


@dataclass(frozen=True)
class Entry(Generic[T]):
    """One name of a :class:`Registry`.

    Attributes:
        name: The name users type (``--generator mpc``).
        summary: One line for the listing command.
        load: Returns what the name stands for (a class, a factory, a configuration);
            called on demand, so heavy imports wait until the name is used.
        is_available: Whether it runs on this installation (called on demand).
        install: How to install it when it is not available (a command or a sentence).
    """

    name: str
    summary: str
    load: Callable[[], T]
    is_available: Callable[[], bool] = _always
    install: str = ""


class Registry(Generic[T]):
    """Entries by name, in the order they were given.

    Args:
        kind: What the entries are, singular (``"pattern generator"``), for messages.
        entries: The entries.
        list_command: The command that lists them (``"mpcwalk generators"``), for messages.
        not_found: Builds the error of an unknown or uninstalled name from the name, the
            available names, the installable ones and the name's own install hint (default:
            :class:`~mpcwalk.exceptions.NotRegistered`).
    """

    def __init__(
        self,
        kind: str,
        entries: Iterable[Entry[T]] = (),
        *,
        list_command: str,
        not_found: Callable[[str, Sequence[str], dict[str, str], str], Exception] | None = None,
    ) -> None:
        self.kind = kind
        self.list_command = list_command
        self._not_found = not_found
        self._entries: dict[str, Entry[T]] = {}
        for entry in entries:
            self.register(entry)

    def register(self, entry: Entry[T]) -> None:
        """Add ``entry``; a name registered twice is a programming error.

        Raises:
            ValueError: The name is taken.
        """
        if entry.name in self._entries:
            raise ValueError(f"The {self.kind} '{entry.name}' is registered already.")
        self._entries[entry.name] = entry

    def names(self, *, available: bool = True) -> list[str]:
        """The names, in order; those that run on this installation unless ``available`` is
        False."""
        return [n for n, e in self._entries.items() if not available or e.is_available()]

    def installable(self) -> dict[str, str]:
        """Known names that do not run on this installation -> how to install them."""
        return {n: e.install for n, e in self._entries.items() if not e.is_available()}

    def entry(self, name: str) -> Entry[T]:
        """The entry called ``name``, available or not.

        Raises:
            NotRegistered: Unknown name (the message lists the names and the listing
                command); the registry's own error where it has one.
        """
        found = self._entries.get(name) if isinstance(name, str) else None
        if found is None:
            raise self._error(name, "")
        return found

    def load(self, name: str) -> T:
        """What ``name`` stands for.

        Raises:
            NotRegistered: Unknown name, or a known one that is not installed (the message
                says how to install it).
        """
        entry = self.entry(name)
        if not entry.is_available():
            raise self._error(name, entry.install or "see its documentation")
        return entry.load()

    def rows(self) -> list[tuple[str, str, bool, str]]:
        """``(name, summary, available, install)`` of every entry, for the listing command."""
        return [(e.name, e.summary, e.is_available(), e.install) for e in self._entries.values()]

    def __contains__(self, name: object) -> bool:
        return name in self._entries

    def __iter__(self) -> Iterator[str]:
        return iter(self._entries)

    def __len__(self) -> int:
        return len(self._entries)

    def _error(self, name: str, install: str) -> Exception:
        if self._not_found is not None:
            return self._not_found(name, self.names(), self.installable(), install)
        return NotRegistered(
            self.kind,
            name,
            self.names(),
            self.installable(),
            install=install,
            list_command=self.list_command,
        )


def format_registry(registry: Registry) -> str:
    """The listing of a registry: one line per entry, name and summary, then the names that
    are not installed with how to install them."""
    rows = registry.rows()
    width = max((len(name) for name, *_ in rows), default=0)
    lines = [f"{name:<{width}}  {summary}" for name, summary, ok, _ in rows if ok]
    missing = [(name, install) for name, _, ok, install in rows if not ok]
    if missing:
        lines.append("")
        lines.append("not installed:")
        lines += [f"  {name:<{width}}  {install}" for name, install in missing]
    return "\n".join(lines)


__all__ = ["Entry", "Registry", "format_registry"]
