"""Reduced models: LIPM, cart-table, CoM state, support polygons."""

from mpcwalk.models.cart_table import CartTable
from mpcwalk.models.com_state import ComState
from mpcwalk.models.lipm import GRAVITY, LIPM
from mpcwalk.models.support_polygon import (
    SupportPolygon,
    convex_hull,
    foot_rectangle,
    sole_footprint,
)

__all__ = [
    "GRAVITY",
    "LIPM",
    "CartTable",
    "ComState",
    "SupportPolygon",
    "convex_hull",
    "foot_rectangle",
    "sole_footprint",
]
