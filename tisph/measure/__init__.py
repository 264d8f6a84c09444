"""Measurement: what a run reads from its particles (the surface, Shepard-interpolated fields),
how a record is analysed (wave heights and periods, harmonics, reflection, spectra), the gauges
that do both each probe, the PI drive of a periodic current, and figures saved whole."""
