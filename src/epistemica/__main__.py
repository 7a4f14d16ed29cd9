"""Run the command-line interface: ``python -m epistemica``."""

import sys

from epistemica.cli import main

sys.exit(main())
