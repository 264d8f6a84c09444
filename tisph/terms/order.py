"""A running maximum as an integer: the IEEE bits of a non-negative float, read as a signed
integer of its width, order as the floats do, so max over them is max over the floats. LLVM
vectorises an integer maximum across the pair loop's lanes; a float one it does not (measured:
`python -m tisph.bench --lanes`), so a pair term's maximum (the viscous signal speed) is kept in
bits and read back once a particle."""

import taichi as ti


@ti.func
def to_bits(x, bits: ti.template()):
    """x >= 0 (a -0.0 reads as a negative integer, below +0.0's 0) as its bits."""
    return ti.bit_cast(x, bits)


@ti.func
def from_bits(b, real: ti.template()):
    return ti.bit_cast(b, real)
