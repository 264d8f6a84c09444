"""The particle store: the particles' fields (the state, its sorted copy, a backup of the last
healthy state), reads and writes of them by particle id, and what they take on the device.

The solver steps the store; it does not own its fields. Inside the step kernel the modules reach
the state as S.p and the sorted copy the neighbour pass reads as S.tmp: the store's two
ParticleFields, handed to the solver once. Everything in Python scope (the run loop, the
checkpoints, the snapshots) goes through the store's methods."""

import numpy as np
import taichi as ti

from .state import ParticleFields, load_particles, np_dtype, type_bytes


@ti.data_oriented
class ParticleStore:
    def __init__(self, members, eval_types, n, fp):
        """members: {name: Taichi type} a step carries over (the core's and the modules');
        eval_types: the evaluation state only the sorted copy has; n particles; fp: NumPy float."""
        self.n, self.fp = n, fp
        self.members = tuple(members)
        self.types, self.eval_types = dict(members), dict(eval_types)
        self.p = ParticleFields(self.types, n)
        self.tmp = ParticleFields(dict(self.types, **self.eval_types), n)
        # (state, sorted copy) pairs: the reorder copies every member in one compile-time loop
        self.pairs = [(getattr(self.p, k), getattr(self.tmp, k)) for k in self.members]
        self.bak = None

    def load(self, particles):
        """A ParticleSet's initial state; ids in the order the scene built them."""
        load_particles(self.p, particles, self.fp)

    def by_id(self, names, fields=None):
        """Arrays of `names` ordered by particle id (kind and mat as 32-bit integers)."""
        f = fields or self.p
        inv = np.argsort(f.id.to_numpy())
        out = {k: getattr(f, k).to_numpy()[inv] for k in names}
        for k, a in out.items():  # kind and mat are bytes on the CPU: the outputs keep 32 bits
            if a.dtype == np.int8:
                out[k] = a.astype(np.int32)
        return out

    def arrays(self):
        """Every member in the current (sorted) order: what a checkpoint keeps."""
        return {k: getattr(self.p, k).to_numpy() for k in self.members}

    def write(self, arrays):
        """Every member back from arrays() as a checkpoint kept them."""
        missing = [k for k in self.members if k not in arrays]
        if missing:
            raise ValueError(f"checkpoint lacks particle fields {missing} (built with other physics?)")
        for k in self.members:
            f = getattr(self.p, k)
            f.from_numpy(np.asarray(arrays[k]).astype(np_dtype(f), copy=False))

    def enable_backup(self):
        """A device-side copy of the state (the last healthy one, for the final snapshot of a run
        that goes unstable); backup() costs one copy of the fields."""
        if self.bak is None:
            self.bak = ParticleFields(self.types, self.n)
            self.bak_pairs = [(getattr(self.p, k), getattr(self.bak, k)) for k in self.members]

    @ti.kernel
    def backup(self):
        for i in range(self.n):
            for fp, fb in ti.static(self.bak_pairs):
                fb[i] = fp[i]

    def nbytes(self):
        """Bytes the particle fields take (from their shapes and types)."""

        def size(types):
            return sum(type_bytes(t) for t in types.values())

        copies = 2 + (self.bak is not None)  # the state, the sorted copy, the backup
        return (size(self.types) * copies + size(self.eval_types)) * self.n
