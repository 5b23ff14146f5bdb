"""Reduced models: LIPM, cart-table, support polygons."""

from mpcwalk.models.cart_table import CartTable
from mpcwalk.models.lipm import GRAVITY, LIPM
from mpcwalk.models.support_polygon import SupportPolygon, convex_hull, foot_rectangle

__all__ = ["GRAVITY", "LIPM", "CartTable", "SupportPolygon", "convex_hull", "foot_rectangle"]
