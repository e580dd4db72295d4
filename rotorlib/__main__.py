"""``python -m rotorlib``: see :mod:`rotorlib.cli`."""

import sys

from .cli import main

sys.exit(main())
