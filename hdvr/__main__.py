"""``python -m hdvr`` runs the CLI."""

import sys

from hdvr.cli import main

sys.exit(main())
