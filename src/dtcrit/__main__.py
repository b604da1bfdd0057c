"""``python -m dtcrit`` runs the same command line as ``dtcrit``."""
from dtcrit.cli import main

raise SystemExit(main())
