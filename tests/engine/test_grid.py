"""The cell grid finds exactly the neighbours brute force finds, edges and corner cells included."""

import numpy as np
import pytest

from tisph.engine.solver import Solver
from tisph.particles import WALL, ParticleSet
from tisph.settings.config import Physics


def make_solver(x, lo, hi, h, wall="repulsive"):
    """wall "repulsive": the branch form (its view hook is not lane-safe), cells half the
    support wide; "dynamic": the lanes, at h = 1.3 dx in cells of the whole support."""
    ps = ParticleSet()
    ps.add(x, WALL, 0, 1000.0, 1.0)
    mats = [dict(name="w", rho0=1000.0, viscosity=0.0, B=1e5)]
    return Solver(Physics(wall=wall, artificial_viscosity=False), ps, mats, (lo, hi), dict(dx=h / 1.3, h=h, c0=10.0))


def brute(x, support):
    x = x.astype(np.float32)
    d = x[:, None, :] - x[None, :, :]
    r2 = (d * d).sum(-1)
    nb = (r2 < np.float32(support) ** 2) & ~np.eye(len(x), dtype=bool)
    ids = np.arange(len(x))
    return nb.sum(1), (nb * ids[None, :]).sum(1)


@pytest.mark.parametrize("seed", [0, 1])
def test_cell_list_equals_brute_force(seed):
    rng = np.random.default_rng(seed)
    lo, hi = np.array([-0.3, 0.1]), np.array([1.2, 0.9])
    h = 0.05
    x = lo + rng.random((1500, 2)) * (hi - lo)
    # points on the domain edges, in the corner cells, and clustered in cell 0
    edges = np.array(
        [
            lo,
            [hi[0] - 1e-6, lo[1]],
            [lo[0], hi[1] - 1e-6],
            hi - 1e-6,
            [lo[0], 0.5],
            [hi[0] - 1e-6, 0.5],
            [0.4, lo[1]],
            [0.4, hi[1] - 1e-6],
        ]
    )
    cell0 = lo + rng.random((30, 2)) * 0.05
    x = np.vstack([x, edges, cell0])
    s = make_solver(x, lo, hi, h)
    cnt, ids = s.neighbour_stats()
    bc, bi = brute(x, s.support)
    assert s.leaked == 0
    assert cnt.sum() > 0
    assert np.array_equal(cnt, bc)
    assert np.array_equal(ids, bi)


@pytest.mark.parametrize(
    "width, wall, cdiv", [(0.15, "repulsive", 2), (1.5, "repulsive", 2), (0.3, "dynamic", 1), (1.5, "dynamic", 1)]
)
def test_the_lanes_visit_what_brute_force_finds(width, wall, cdiv):
    """The force pass's vector lanes (grid.py): each stencil row padded to whole eights and to
    at least 32 candidates, the padding out of reach, in cells of half the support (5 x 5) and of
    the whole (3 x 3). In a domain three cells wide a padded row runs on into the next row of
    cells, within the support: counted only once."""
    rng = np.random.default_rng(2)
    lo, hi = np.array([0.0, 0.0]), np.array([width, 1.0])
    x = lo + rng.random((int(4000 * width) if width < 1 else 2000, 2)) * (hi - lo)
    s = make_solver(x, lo, hi, 0.05, wall)
    assert s.grid.cdiv == cdiv and s.lanes == (wall == "dynamic")
    assert (s.grid.nx == 3) == (width < 1)
    cnt, ids = s.neighbour_stats(lanes=True)
    bc, bi = brute(x, s.support)
    assert cnt.sum() > 0
    assert np.array_equal(cnt, bc)
    assert np.array_equal(ids, bi)


def test_particle_outside_domain_is_counted_not_dropped():
    lo, hi = np.array([0.0, 0.0]), np.array([1.0, 1.0])
    x = np.array([[0.5, 0.5], [0.52, 0.5], [1.5, 0.5], [0.5, -0.2]])
    s = make_solver(x, lo, hi, 0.05)
    s.prime()
    assert s.leaked == 2
    st = s.state(("kind",))
    assert list(st["kind"]) == [WALL, WALL, -1, -1]
    cnt, _ = s.neighbour_stats()
    assert cnt[0] == 1 and cnt[1] == 1
