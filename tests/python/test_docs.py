"""Every ```python block of docs/python.md and docs/coupling.md runs (from the repository root, as
the pages say) and prints what the page says it prints: the block's output must match the
```text block that follows it, or the `It prints `...`` line after it."""

import os
import re
import subprocess
import sys
import unittest

SOURCE = os.environ.get("QUARRY_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
PAGES = [os.path.join(SOURCE, "docs", name) for name in ("python.md", "coupling.md")]


def examples(page):
    """(code, expected output or None) of every python block of the page, in page order."""
    with open(page, encoding="utf-8") as f:
        text = f.read()
    found = []
    for match in re.finditer(r"```python\n(.*?)```\n", text, flags=re.S):
        after = text[match.end() :]
        printed = re.match(r"\s*It prints\s*\n*```text\n(.*?)```", after, flags=re.S)
        inline = re.match(r"\s*It prints `(.*?)`\.", after, flags=re.S)
        expected = printed.group(1) if printed else inline.group(1) + "\n" if inline else None
        found.append((match.group(1), expected))
    return found


class Docs(unittest.TestCase):
    def test_every_example_runs_and_prints_what_the_page_says(self):
        for page in PAGES:
            blocks = examples(page)
            self.assertGreaterEqual(len(blocks), 1, page)
            name = os.path.relpath(page, SOURCE)
            for number, (code, expected) in enumerate(blocks, 1):
                with self.subTest(page=name, block=number):
                    result = subprocess.run(
                        [sys.executable, "-c", code], cwd=SOURCE, capture_output=True, text=True
                    )
                    self.assertEqual(result.returncode, 0, result.stderr)
                    print("\n--- %s, python block %d:\n%s" % (name, number, result.stdout), end="")
                    if expected is not None:
                        self.assertEqual(result.stdout, expected)


if __name__ == "__main__":
    unittest.main()
