"""Material tables that several scenes share (each scene copies them into its DEFAULTS)."""

WATER = {
    "rho0": 1000.0,  # rest density (kg/m3)
    "viscosity": 1.0e-3,
}  # dynamic viscosity (Pa s; a Bingham material's plastic viscosity mu_B)

# Saturated sand as a Bingham fluid, paper 000 section 5: 1950 kg/m3, mu_B = 0.1 Pa s, tau_B =
# 200 Pa (beach_bingham_tau1000.toml: 1000 Pa); an unyielded bed rests as a rigid plug.
BINGHAM_SAND = {
    "rho0": 1950.0,
    "viscosity": 0.1,
    "rheology": "bingham",  # newtonian | bingham (paper 000 eqs. 13-14) | cross (paper 002 eqs. 29-30)
    "yield_stress": 200.0,  # tau_B (Pa)
    "regularisation": 100.0,  # Papanastasiou exponent m (s): mu = mu_B + tau_B (1 - exp(-m gamma)) / gamma
    "mu_max": 0.0,  # cap on the effective viscosity (Pa s); 0: where its explicit step meets the acoustic one
    "unyielded": "rest",
}
