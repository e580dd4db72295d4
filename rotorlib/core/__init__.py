"""The system and its flow: equations, energies, elliptic functions, precision tiers."""
