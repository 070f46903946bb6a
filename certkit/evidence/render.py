"""Rendering a report view: Jinja2 templates to self-contained HTML, WeasyPrint to PDF/A-3b
with the fonts embedded; nothing is fetched from outside the templates and the fonts.

WeasyPrint is imported where a PDF is made, not at the top: it adds about 0.45 s to every
start-up (``python -X importtime``), and validate, audit and the HTML need none of it.
"""

from __future__ import annotations

import contextlib
import datetime as dt
import importlib.util
import io
import os
from pathlib import Path
from urllib.parse import unquote, urlparse

from jinja2 import Environment, FileSystemLoader, StrictUndefined, select_autoescape
from markupsafe import Markup


def templates_dir() -> Path:
    """The Jinja2 templates: packaged copy in a wheel, the repository's templates/ otherwise."""
    package = Path(__file__).resolve().parent.parent
    packaged = package / "_templates"
    return packaged if packaged.is_dir() else package.parent / "templates"


def fonts_dir() -> Path:
    """DejaVu fonts shipped with matplotlib (a core dependency): embedded in every PDF.

    Located without importing matplotlib (a report without figures does not need it)."""
    spec = importlib.util.find_spec("matplotlib")
    return Path(spec.submodule_search_locations[0]) / "mpl-data" / "fonts" / "ttf"


# --------------------------------------------------------------------------- HTML and PDF
def _environment() -> Environment:
    return Environment(loader=FileSystemLoader(str(templates_dir())),
                       autoescape=select_autoescape(default=True, default_for_string=True),
                       undefined=StrictUndefined, trim_blocks=True, lstrip_blocks=True,
                       keep_trailing_newline=True)


def render_html(view: dict) -> str:
    """The self-contained report HTML (inline CSS and SVG, nothing fetched)."""
    css = (templates_dir() / "report.css").read_text(encoding="utf-8")
    return _environment().get_template("report.html.j2").render(view=view, css=Markup(css))


class _LocalOnlyFetcher:
    """URL fetcher for WeasyPrint that serves only the templates and the font folder."""

    def __init__(self, roots: list[Path]):
        from weasyprint.urls import URLFetcher
        self._fetcher = URLFetcher(allowed_protocols=("file", "data"))
        self._fail_on_errors = True
        self.roots = [root.resolve() for root in roots]

    def __call__(self, url: str):

        from weasyprint.urls import FatalURLFetchingError
        parsed = urlparse(url)
        if parsed.scheme == "file":
            path = Path(unquote(parsed.path)).resolve()
            if not any(path.is_relative_to(root) for root in self.roots):
                raise FatalURLFetchingError(f"refused to fetch {url}: outside the report's folders")
        elif parsed.scheme != "data":
            raise FatalURLFetchingError(f"refused to fetch {url}: only local files are used")
        return self._fetcher.fetch(url)


def _font_css() -> str:
    faces = []
    for name, weight, style in (("DejaVuSans.ttf", "normal", "normal"),
                                ("DejaVuSans-Bold.ttf", "bold", "normal"),
                                ("DejaVuSans-Oblique.ttf", "normal", "italic"),
                                ("DejaVuSansMono.ttf", "normal", "normal")):
        family = "DejaVu Sans Mono" if "Mono" in name else "DejaVu Sans"
        faces.append(f"@font-face {{ font-family: '{family}'; src: url('{(fonts_dir() / name).as_uri()}');"
                     f" font-weight: {weight}; font-style: {style}; }}")
    return "\n".join(faces)


#: The modification stamp of the embedded font subsets (1970-01-01, POSIX time 0): the fonts'
#: own, fixed, so the same report gives the same bytes.  It is not the document date: a
#: font's stamp counts from 1904 and cannot go before it, a document date can (1903-12-31).
FONT_EPOCH = 0


@contextlib.contextmanager
def _source_date_epoch(epoch: int):
    """fontTools stamps subset fonts with the current time unless SOURCE_DATE_EPOCH is set
    (WeasyPrint subsets with it where HarfBuzz cannot)."""
    previous = os.environ.get("SOURCE_DATE_EPOCH")
    os.environ["SOURCE_DATE_EPOCH"] = str(epoch)
    try:
        yield
    finally:
        if previous is None:
            del os.environ["SOURCE_DATE_EPOCH"]
        else:
            os.environ["SOURCE_DATE_EPOCH"] = previous


#: WeasyPrint's options for the report: PDF/A-3b, compressed
PDF_OPTIONS = {"pdf_variant": "pdf/a-3b", "uncompressed_pdf": False}


def laid_out(html: str, **options):
    """The report's pages as WeasyPrint lays them out (a ``weasyprint.document.Document``:
    its ``pages`` hold the boxes, where a check can see what a page break left where)."""
    from weasyprint import CSS, DEFAULT_OPTIONS, HTML
    from weasyprint.text.fonts import FontConfiguration

    fetcher = _LocalOnlyFetcher([templates_dir(), fonts_dir()])
    fonts = FontConfiguration()
    document = HTML(string=html, base_url=str(templates_dir()) + "/", url_fetcher=fetcher)
    return document.render(
        font_config=fonts,
        **{**DEFAULT_OPTIONS, **PDF_OPTIONS, **options,
           "stylesheets": [CSS(string=_font_css(), font_config=fonts, url_fetcher=fetcher)]})


def render_pdf(html: str, attachments: list[tuple[str, bytes, str]], date: dt.date) -> bytes:
    """PDF/A-3b of the report with ``attachments`` (name, bytes, relationship) embedded."""
    from weasyprint import DEFAULT_OPTIONS, Attachment

    stamp = dt.datetime(date.year, date.month, date.day, tzinfo=dt.timezone.utc)
    fetcher = _LocalOnlyFetcher([templates_dir(), fonts_dir()])
    files = [Attachment(file_obj=io.BytesIO(content), name=name, created=stamp, modified=stamp,
                        relationship=relationship, url_fetcher=fetcher)
             for name, content, relationship in attachments]
    with _source_date_epoch(FONT_EPOCH):
        return laid_out(html, attachments=files).write_pdf(
            **{**DEFAULT_OPTIONS, **PDF_OPTIONS, "attachments": files})
