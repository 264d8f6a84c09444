"""The module interface: each piece of physics and each boundary treatment is one Module.

A module declares what it needs and contributes @ti.func hooks; the step kernel
(tisph/engine/stepper.py) calls the hooks of the enabled modules in registry order, unrolled
with ti.static, so a module that is off is neither allocated nor traced.

Declarations (class attributes, all optional):
  fields(real)   particle members it allocates: {name: taichi type}
  material       per-material parameters: {name: MatParam}; read from the material dicts, held
                 by the parameter table (engine/table.py) and read as S.mat.<name>[material]
  params         runtime parameters (a Taichi struct field, changeable without a recompile):
                 {name: Param}; each has its ONE default, unit and allowed range; read as
                 S.prm[None].<name>
  acc            accumulator slots it adds to a fluid particle's neighbour sum: {name: type}
  stats          per-step statistics slots it adds (counters): {name: type}
  maxima         per-step maxima it adds: {name: type}; its finish hook raises pt.<name>,
                 which the solver reduces per block of particles (no atomics)
  rate           "advection" for a term that changes at the flow's pace (dual time stepping, physics/dual.py)
  pair_once      the acc slots it sums ({slot: 'sum' | 'max'}) when it has a pair2 hook and its
                 pair hook also gives j's term when called as pair(S, j, i, -r, r2, <j's view
                 of i>, <j's acc>): each pair is then visited once (engine/pairs.py)

Hooks (define only those the module uses; `S` is the kernel view, engine/view.py, but in
after_step, which runs in Python, the solver):
  drift(S, i, u) -> u              fluid drift velocity (XSPH)
  move(S, i, dt)                   a MOVING boundary particle's prescribed motion (paddle)
  boundary_motion(S, i, k, dt)     any other boundary's motion by kind (the moving sand bed)
  boundary_kick(S, i, dt)          a boundary particle's half kick (dynamic walls)
  remove(S, i) -> gone             fluid leaving through an open boundary (outflow)
  position_check(S, i)             fluid in a forbidden place (container)
  prepare(S, a, dt)                a boundary particle's evaluation state (dynamic walls)
  init_acc(S, i, acc)              load particle i's own values into its accumulator
  view(S, i, j, r, r2, nb, acc)    change how i sees neighbour j before the terms (pressure mirror)
  pair(S, i, j, r, r2, nb, acc)    add j's contribution to i's sums
  pair2(S, i, j, r, r2, nb, acc, sj)  a fluid pair's terms for both: i's into acc, j's into sj
                                   (nb also holds m_i and vol_i); each pair once only
  body_force(S, i, mi, a) -> a     a body force per material (periodic drive)
  relax(S, i, mi, v, dt) -> v      a velocity relaxation after the kick (damping, inflow zones)
  finish(S, i, mi, acc, pt)        per particle after the neighbour pass (stress, viscosity)
  hold(S, i, mi, pt)               an advection-rate module on a dual step that holds its sums:
                                   what it still does every step (the k equation's own step)
  boundary_pass(S, i, dt)          a boundary particle's own neighbour pass (dynamic walls)
  dt_limit(S, st, dt) -> dt        a bound on the next time step
  after_step(S)                    Python, after the kernel (Shepard filter)
"""

import dataclasses

from ..settings.schema import Param  # noqa: F401 (re-exported: the modules declare theirs with it)

HOOKS = (
    "drift",
    "move",
    "boundary_motion",
    "boundary_kick",
    "remove",
    "position_check",
    "prepare",
    "init_acc",
    "view",
    "pair",
    "pair2",
    "body_force",
    "relax",
    "finish",
    "hold",
    "boundary_pass",
    "dt_limit",
    "after_step",
)


@dataclasses.dataclass(frozen=True)
class MatParam:
    """A per-material parameter: default, unit, doc; kind 'real' or 'int'. convert(value, mat, S)
    turns the material dict's value (or the default) into the stored number."""

    default: object
    unit: str = "-"
    doc: str = ""
    kind: str = "real"
    convert: object = None
    field: str = ""  # the field is S.mat.<field> (default: the key)


class Module:
    """Base of every module. `enabled(physics)` says whether a case compiles it in."""

    name = "module"
    on = None  # the switches that turn it on (Physics fields; outflow/container: solver
    # arguments); None: always on. The tests build every module from this.
    material = {}
    params = {}
    acc = {}
    stats = {}
    maxima = {}
    pair_once = None  # {acc slot: "sum" | "max"} it sums, with a pair2 hook (engine/pairs.py)
    # "advection": with numerics.time_stepping = "dual", its pair and finish hooks run only on the
    # steps that evaluate the terms that change at the flow's pace, its sums held between (physics/dual.py)
    rate = "acoustic"
    # True: its pair, view and boundary-pass neighbour tasks are right for any candidate j, a
    # term past the kernel's support being zero without a branch, and compile to loads and
    # selects the CPU's vector lanes can take (engine/grid.py, for_neighbours' lanes)
    lanes = False

    def __init__(self, S=None):
        """S: the solver being built (its physics; its fields do not exist yet). A module whose
        sums or fields depend on a switch sets them here."""

    @classmethod
    def enabled(cls, S):
        """On when every switch in `on` holds (a tuple switch: non-empty); override for others."""
        if cls.on is None:
            return True
        for k, want in cls.on.items():
            have = getattr(S.physics, k) if hasattr(S.physics, k) else getattr(S, k)
            if isinstance(want, tuple):
                ok = bool(have)
            elif isinstance(want, bool):
                ok = bool(have) == want
            else:
                ok = have == want
            if not ok:
                return False
        return True

    def fields(self, real):
        return {}

    def allocate(self, S):
        """Create fields that are not per particle (before any field is written)."""

    def setup(self, S):
        """Python-side set-up once the solver's fields exist and hold their values."""

    def has(self, hook):
        return callable(getattr(type(self), hook, None))
