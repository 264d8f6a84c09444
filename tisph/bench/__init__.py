"""Benchmarks and validation runs: python -m tisph.bench (cli.py reads the options and dispatches).

cli.py              the options, and which benchmark runs
ladder.py           run time against error at a ladder of resolutions
engine_costs.py     the ladder's scaling, specialisation and kernel-profile sections
validate.py         --validate: every validation case; validation_cases.py lists them, and
                    validation_page.py writes docs/validation.md and the README's table
against.py          --validate --against REV: validation cases run whole on both trees, the time to each error
uncertainty.py      each validation case's interval: its GCI, or its seeds' standard error
speed.py            --speed: particle-steps/s, optionally against another revision, back to back
traffic.py          --traffic: kernel launches and host-device transfers a step
scheme_costs.py     --schemes: run time against error under each numerics scheme
gci_examples.py     --convergence: the breakwater and the seawall at three spacings
shedding.py         --shedding: a pipe's wake over a fixed bed against the gap
mao_held.py         --mao-held: Mao's measured beds held still under the pipeline's flow
ripple_sweep.py     --ripples: the tunnel's ripples against the orbital diameter (the Dask sweep)
ripple_report.py    its report: the band, the table, the figures
standing.py         --standing: a standing wave's loss per period under each density diffusion
peers/              PySPH and DualSPHysics beside tisph (a clone only: not in the wheel)
"""
