"""Rewrite the guide's schema tables (docs/guide.md) from relacc.fixtures.schema (tests/test_readme.py checks they
match).

Run:  python scripts/readme_tables.py
"""

import re
from pathlib import Path

from relacc.files import write_text
from relacc.fixtures.schema import ChainFile, SceneFile, markdown_table

README = Path(__file__).resolve().parents[1] / "docs" / "guide.md"

text = README.read_text()
for name, schema in (("chain", ChainFile), ("scene", SceneFile)):
    text = re.sub(rf"(<!-- schema:{name} -->\n).*?(\n<!-- /schema:{name} -->)",
                  lambda m, s=schema: m.group(1) + markdown_table(s) + m.group(2), text, flags=re.S)
write_text(README, text)
print(f"updated {README}")
