"""New science beyond the paper: the atlas, choreographies, the quantum 3-rotor."""
