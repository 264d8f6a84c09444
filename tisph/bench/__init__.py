"""Benchmarks and validation runs: python -m tisph.bench (cli.py reads the options and dispatches).

cli.py        the options, and which benchmark runs
ladder.py     run time against error at a ladder of resolutions, scaling, the kernel profile
validate.py   --validate: every validation case, written as docs/validation.md
speed.py      --speed: particle-steps/s, optionally against another revision, back to back
peer.py       --peer pysph: PySPH's dam break beside ours
shedding.py   --shedding: a pipe's wake over a fixed bed against the gap
mao_held.py   --mao-held: Mao's measured beds held still under the pipeline's flow
ripples.py    --ripples: the tunnel's ripples against the orbital diameter (the Dask sweep)
waves.py      --waves: the default flume against Biesel, tisph and DualSPHysics at equal dp
standing.py   --standing: a standing wave's loss per period under each density diffusion
"""
