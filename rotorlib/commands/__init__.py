"""Subcommands of ``python -m rotorlib`` (one module each, registered in :mod:`rotorlib.cli`)."""
