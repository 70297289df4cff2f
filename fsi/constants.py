"""Physical constants and the thesis's reference values (SI units), each defined once.

Levine (2014), Table 4.1 / App. B parameters.
"""
STANDARD_GRAVITY = 9.81  # m/s^2, thesis gravity (0, 0, -9.81)
TANK_RADIUS = 0.20955  # m, 16.5 in spherical tank (thesis Radius)
MEMBRANE_THICKNESS = 0.001778  # m, AF-E-332 diaphragm (thesis Thickness)
MEMBRANE_DENSITY = 1070.0  # kg/m^3 (thesis rhoMembrane)
MEMBRANE_YOUNGS_MODULUS = 8.6e6  # Pa (thesis E)
WATER_DENSITY = 1000.0  # kg/m^3 (thesis rho)
THESIS_RUNTIME_SECONDS = 24_600.0  # s, 6 h 50 min MATLAB static run (Table 4.1)
HALF_SPHERE_LAMBDA1 = 1.5602  # omega_1^2 R / g, half-full rigid sphere, free surface (Budiansky 1960)
EQN_6_1_CENTRE_FRACTION = 0.8  # nodes with |x| < 0.8 R enter the Eqn 6.1 error
