"""The engine: particle state, cell grid, the one fused step kernel, time-step limits, health.

The physics and boundary treatments are modules (tisph/physics, tisph/boundaries) that the step
kernel composes at trace time; see tisph/hooks/module.py for the interface.
"""
