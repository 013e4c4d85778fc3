"""``python -m flexarm.cli``: the ``flexarm`` command."""

import sys

from . import main

sys.exit(main())
