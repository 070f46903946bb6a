"""The documentation's examples run: `make docs` runs this file after building the site.

* Every ```` ```console ```` block of a page is a shell session: its ``$ `` lines run in
  order, in one bash process per page, from a fresh folder that holds the repository's
  ``docs/`` and ``campaigns/`` (as a reader's clone does), with certkit's environment on
  the PATH. Each command must exit 0, and every output line the page shows must appear in
  what the command printed (blanks squeezed). A command meant to fail shows its exit code
  itself (``cmd; echo "exit code $?"``).
* Every ``>>>`` example of a page runs as a doctest (``pytest --doctest-glob``, which
  `make docs` passes).
* Every link of the built site leads somewhere: a page, a file and an anchor that exist.
  External links (``http:``, ``https:``) are listed by ``make docs-linkcheck``, which needs
  the network; the build machine of CI has none beyond the package registries.
"""

from __future__ import annotations

import functools
import html.parser
import os
import re
import subprocess
import sys
from pathlib import Path
from urllib.parse import unquote, urlsplit

import pytest

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
SITE = DOCS / "_build" / "html"
PAGES = sorted(p for p in DOCS.glob("*.md") if p.name != "spec-reference.md")
MARK = "@@certkit-docs-rc="


def sessions(page: Path) -> list[tuple[str, list[str]]]:
    """(command, expected output lines) of every ``$`` line of the page's console blocks."""
    steps: list[tuple[str, list[str]]] = []
    inside = False
    for line in page.read_text(encoding="utf-8").splitlines():
        if line.startswith("```"):
            inside = line.strip() == "```console" if not inside else False
            continue
        if not inside:
            continue
        if line.startswith("$ "):
            steps.append((line[2:], []))
        elif steps and line.strip():
            steps[-1][1].append(line)
    return steps


def _squeezed(text: str) -> str:
    return " ".join(text.split())


@pytest.mark.parametrize("page", [p for p in PAGES if sessions(p)], ids=lambda p: p.stem)
def test_console_sessions_run_as_shown(page, tmp_path):
    for name in ("docs", "campaigns"):
        (tmp_path / name).symlink_to(ROOT / name)
    steps = sessions(page)
    # standard error joins standard output, in order: a page shows what a terminal shows
    script = "exec 2>&1\n" + "".join(f"{command}\necho '{MARK}'$?\n" for command, _ in steps)
    environment = dict(os.environ, PATH=f"{Path(sys.executable).parent}:{os.environ['PATH']}",
                       COLUMNS="200", NO_COLOR="1")
    done = subprocess.run(["bash", "-c", script], cwd=tmp_path, capture_output=True,
                          text=True, env=environment, timeout=900)
    outputs = re.split(re.escape(MARK) + r"(\d+)\n", done.stdout + "\n")
    printed = outputs[0:-1:2]
    codes = [int(code) for code in outputs[1::2]]
    assert len(codes) == len(steps), f"{page.name}: the session stopped early\n{done.stdout}"
    for (command, expected), output, code in zip(steps, printed, codes):
        assert code == 0, f"{page.name}: `{command}` exited {code}\n{output}"
        for line in expected:
            assert _squeezed(line) in _squeezed(output), (
                f"{page.name}: `{command}` did not print\n  {line}\nit printed:\n{output}")


class _Links(html.parser.HTMLParser):
    def __init__(self):
        super().__init__()
        self.links: list[str] = []
        self.ids: set[str] = set()

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        if attrs.get("id"):
            self.ids.add(attrs["id"])
        for key in ("href", "src"):
            if attrs.get(key) and not (tag == "link" and attrs.get("rel") == "preload"):
                self.links.append(attrs[key])


@functools.cache
def _parsed(page: Path) -> _Links:
    parser = _Links()
    parser.feed(page.read_text(encoding="utf-8"))
    return parser


def test_every_link_of_the_site_leads_somewhere():
    if not (SITE / "index.html").exists():
        pytest.fail(f"no built site in {SITE}: run `make docs`, which builds it first")
    broken = []
    for page in sorted(p for p in SITE.rglob("*.html") if "_static" not in p.parts):
        for link in _parsed(page).links:
            parts = urlsplit(link)
            if parts.scheme in ("http", "https", "mailto", "data", "javascript"):
                continue
            target = page if not parts.path else (page.parent / unquote(parts.path)).resolve()
            if target.is_dir():
                target = target / "index.html"
            if not target.exists():
                broken.append(f"{page.relative_to(SITE)}: {link} (no such file)")
            elif parts.fragment and target.suffix == ".html":
                if unquote(parts.fragment) not in _parsed(target).ids:
                    broken.append(f"{page.relative_to(SITE)}: {link} (no such anchor)")
    assert not broken, "broken links:\n" + "\n".join(broken)
