"""``python -m poissonkit`` runs the command-line interface."""

from poissonkit.cli import main

raise SystemExit(main())
