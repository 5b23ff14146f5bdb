"""Reduced models: LIPM, cart-table, support polygons."""

from .cart_table import CartTable
from .lipm import GRAVITY, LIPM
from .support_polygon import SupportPolygon, convex_hull, foot_rectangle

__all__ = ["CartTable", "GRAVITY", "LIPM", "SupportPolygon", "convex_hull", "foot_rectangle"]
