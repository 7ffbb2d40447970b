"""``python3 -m flexure sweep SPEC GRID [options]``: flexure.sweep from a shell (docs/sweeps.md)."""

import sys

from .sweep import main

if len(sys.argv) < 2 or sys.argv[1] != "sweep":
    print("usage: python3 -m flexure sweep SPEC GRID [--out DIR] [--scheduler ADDRESS] "
          "[--workers N] [--command FLEXURE] [--report FILE]", file=sys.stderr)
    sys.exit(2)
sys.exit(main(sys.argv[2:]))
