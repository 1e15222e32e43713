"""``python -m wake`` is the ``wake`` command."""

import sys

from wake.cli import main

sys.exit(main())
