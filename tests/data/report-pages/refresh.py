"""Make the reference page images of the example report again, on purpose.

tests/test_rendering.py renders every page of the example campaign's report.pdf (no
drop-model section) to a greyscale PNG at 30 dpi with PDFium (the pypdfium2 wheel) and
compares it with the page-NN.png files in this folder.  When that test fails because the
report's template, stylesheet or wording changed the layout on purpose, look at the pages
it wrote (the failure names the folder; diff-NN.png show what moved) and, if they are
right, run from the repository root

    .venv/bin/python tests/data/report-pages/refresh.py

then commit the images (git add tests/data/report-pages).  Do not run it to make a failure
go away that nobody meant: that is the failure the test is there to catch.

It renders the report exactly as the test does (same function, same resolution), replaces
every page-*.png here and stores them as 8-bit greyscale, optimised (pixel values as
render_pages made them), and records in versions.json what they depend on: WeasyPrint,
pydyf, matplotlib, Pango and pypdfium2 with the PDFium build it ships.  Install with
constraints.txt (make install) and make them on Debian bookworm, as CI runs.
"""

from __future__ import annotations

import json
import shutil
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parents[2]))  # the repository root, for certkit and tests

from PIL import Image  # noqa: E402

from certkit import assess, load_campaign, render_report  # noqa: E402
from tests.conftest import SEED  # noqa: E402
from tests.test_rendering import (DPI, VERSIONS_FILE, compare_pages,  # noqa: E402
                                   reference_pages, render_pages, rendering_versions)


def main() -> None:
    with tempfile.TemporaryDirectory(prefix="certkit-reference-") as scratch:
        out = Path(scratch) / "out"
        render_report(assess(load_campaign(SEED)), out)
        pages = render_pages(out / "report.pdf", Path(scratch) / "pages", DPI)
        again = render_pages(out / "report.pdf", Path(scratch) / "again", DPI)
        if [p.read_bytes() for p in pages] != [p.read_bytes() for p in again]:
            sys.exit("PDFium drew the pages differently twice; nothing was replaced")
        before = reference_pages(HERE)
        changes = compare_pages(pages, before) if before else ["no reference pages before"]
        # the new set is made complete beside the old one, then swapped in
        staged = Path(scratch) / "new"
        staged.mkdir()
        for page in pages:
            with Image.open(page) as image:
                image.convert("L").save(staged / page.name, optimize=True)
        (staged / VERSIONS_FILE.name).write_text(
            json.dumps(rendering_versions(), indent=2) + "\n", encoding="utf-8")
        for old in before:
            old.unlink()
        for new in sorted(staged.iterdir()):
            shutil.copyfile(new, HERE / new.name)
    size = sum(p.stat().st_size for p in reference_pages(HERE))
    print(f"{len(pages)} pages at {DPI} dpi written to {HERE} ({size / 1024:.0f} KiB)")
    print("beyond the tolerance, compared with the previous images:\n  "
          + ("\n  ".join(changes) if changes else "nothing"))


if __name__ == "__main__":
    main()
