"""Plotting helpers (matplotlib), one module per chapter; the numerical modules never import this package."""
