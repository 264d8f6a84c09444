"""Physical constants shared by scenes, probes and the engine (one definition each)."""

G = 9.81        # gravitational acceleration (m/s2)
KAPPA = 0.42    # von Karman's constant of the log law, paper 002 eq. 32
