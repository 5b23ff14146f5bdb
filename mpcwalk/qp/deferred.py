"""Fields of a frozen value that are computed the first time they are read.

A QP generator's tick makes values that the walk itself seldom reads: the residuals of a
solve, the states its plan predicts over the horizon. Their owners (:class:`~mpcwalk.qp.
result.QPResult`, :class:`~mpcwalk.qp.program.Prediction`, the generators' ``Horizon``)
may hold a function of no argument in their place; :func:`resolved` calls it when the
field is first read and keeps the value. The function must compute from arrays that no
later tick changes in place.
"""

from typing import Any


def resolved(owner: object, name: str) -> Any:
    """The value of ``owner``'s field ``name``: when the field holds a function of no
    argument, the function's value, computed now and kept in its place."""
    value = owner.__dict__[name]
    if callable(value):
        value = value()
        object.__setattr__(owner, name, value)
    return value


def deferred_item(name: str, index: int, doc: str) -> Any:
    """A read-only property: item ``index`` of the field ``name`` (:func:`resolved`)."""
    return property(lambda owner: resolved(owner, name)[index], doc=doc)


__all__ = ["deferred_item", "resolved"]
