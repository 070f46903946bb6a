"""The one home of how a page generated from the code joins the site: written into the
source folder when the build starts, and only when its text changed (so that an unchanged
page rebuilds nothing)."""

from pathlib import Path


def register(app, page: str, make_text) -> dict:
    """Have ``page`` written from ``make_text()`` when the build starts; returns what a
    Sphinx extension's ``setup`` returns."""

    def write(app) -> None:
        text = make_text()
        target = Path(app.srcdir) / page
        if not target.exists() or target.read_text(encoding="utf-8") != text:
            target.write_text(text, encoding="utf-8")

    app.connect("builder-inited", write)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
