"""The paper's families: pendulum transitions, newborn orbits, laws, breathers, chaos."""
