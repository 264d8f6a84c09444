"""Probes and controls that scenes share: the PI drive of a periodic current, plot saving."""
