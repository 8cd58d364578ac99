"""Regenerate hdvr/models/dancer.xml (also reachable as models/dancer.xml) from the DH table.

    python scripts/build_dancer_model.py [--check]

With --check, exit 1 if the file on disk differs from what the code generates (a test does the same).
"""

import argparse
import sys
from pathlib import Path

from hdvr.dancer_model import build_mjcf

TARGET = Path(__file__).resolve().parents[1] / "hdvr" / "models" / "dancer.xml"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="only compare, do not write")
    args = parser.parse_args()
    xml = build_mjcf()
    if args.check:
        same = TARGET.is_file() and TARGET.read_text() == xml
        print("up to date" if same else f"{TARGET} differs from the generator")
        return 0 if same else 1
    TARGET.write_text(xml)
    print(f"wrote {TARGET}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
