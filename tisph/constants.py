"""Physical constants shared by scenes, probes and the engine (one definition each)."""

G = 9.81  # gravitational acceleration (m/s2)
KAPPA = 0.42  # von Karman's constant of the log law, paper 002 eq. 32
SQRT_CMU = (
    0.3  # C_mu^(1/2), C_mu = 0.09: k = u*^2 / sqrt(C_mu) in a wall layer in equilibrium (Launder & Spalding 1972)
)
