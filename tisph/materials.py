"""Material tables that several scenes share (each scene copies them into its DEFAULTS)."""

WATER = {"rho0": 1000.0, "viscosity": 1.0e-3}

# Saturated sand as a Bingham fluid, paper 000 section 5: 1950 kg/m3, mu_B = 0.1 Pa s, tau_B =
# 200 Pa (beach_tau1000.toml: 1000 Pa); an unyielded bed rests as a rigid plug.
BINGHAM_SAND = {"rho0": 1950.0, "viscosity": 0.1, "rheology": "bingham", "yield_stress": 200.0,
                "regularisation": 100.0, "mu_max": 0.0, "unyielded": "rest"}
