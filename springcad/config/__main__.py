"""``python -m springcad.config [--readme README.md]``: print the config table or update the README's."""

import argparse
from pathlib import Path

from springcad.config.schema import markdown_table, readme_with_table

ap = argparse.ArgumentParser(description="print the config reference table, or update it in a README")
ap.add_argument("--readme", type=Path, help="rewrite the table between the markers of this file")
ns = ap.parse_args()
if ns.readme:
    ns.readme.write_text(readme_with_table(ns.readme.read_text()))
else:
    print(markdown_table())
