"""The periodic-orbit engine: shooting, continuation, Floquet theory, result types."""
