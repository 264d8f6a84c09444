"""Boundary modules: walls (dynamic, repulsive with pressure mirror, no-slip ghost), zones
(outflow, container check, damping, inflow, periodic drive) and the paddle."""
