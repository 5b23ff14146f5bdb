"""A bounded cache of values made once per key (cost factors, products, matrix values)."""

from collections.abc import Callable, Hashable
from typing import TypeVar

T = TypeVar("T")


def kept(cache: dict, key: Hashable, make: Callable[[], T], size: int) -> T:
    """``cache[key]``, made by ``make()`` the first time it is asked; when ``cache`` already
    holds ``size`` values, the oldest is dropped to make room."""
    if key in cache:
        return cache[key]
    if len(cache) >= size:
        del cache[next(iter(cache))]
    value = cache[key] = make()
    return value
