"""Pair terms of the SPH equations, one module per physical term.

Each is a small @ti.func of the pair's quantities (no field access), so the solver can unroll
the terms a scene enables into one neighbour loop and compile out the rest.
"""
