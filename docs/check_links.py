"""Check that every internal link of a built site resolves: its page exists and, with a ``#fragment``, that
page has an element with that id.  Images and stylesheets are checked the same way.

    python docs/check_links.py docs/_build/html

Sphinx's linkcheck builder fetches external URLs (CI has no internet, so they are ignored there) and
reports a link to an anchor inside the site as "unchecked"; this walks the built HTML instead.  A
Markdown link to a missing page or heading already fails the ``-W`` build (MyST's ``xref_missing``); this
is the check on what the browser will follow, the API pages and the theme's navigation included.
Exit status 1 and one line per broken link when any is found.
"""

from __future__ import annotations

import sys
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urldefrag, urlparse


class _Page(HTMLParser):
    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.ids: set[str] = set()
        self.links: list[str] = []

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        for key in ("id", "name"):
            if attrs.get(key) and (key == "id" or tag == "a"):
                self.ids.add(attrs[key])
        for key in ("href", "src"):
            value = attrs.get(key)
            if value and not (tag == "link" and attrs.get("rel") in ("canonical", "preconnect")):
                self.links.append(value)


def _parse(path: Path) -> _Page:
    page = _Page()
    page.feed(path.read_text(encoding="utf-8", errors="replace"))
    return page


def broken_links(site: Path) -> list[str]:
    """``"page: link (reason)"`` for every internal link of the HTML pages under ``site`` that does not resolve."""
    site = site.resolve()
    # the theme's own template fragments under _static/ are not pages
    pages = {path.resolve(): _parse(path) for path in site.rglob("*.html") if "_static" not in path.parts}
    problems = []
    for path, page in sorted(pages.items()):
        for link in page.links:
            parsed = urlparse(link)
            if parsed.scheme or parsed.netloc or link.startswith(("mailto:", "javascript:", "data:")):
                continue  # external: not fetched (CI has no internet)
            target, fragment = unquote(parsed.path), urldefrag(link)[1]
            resolved = (path.parent / target).resolve() if target else path
            if target.endswith("/") or resolved.is_dir():
                resolved = resolved / "index.html"
            where = f"{path.relative_to(site)}: {link}"
            if site not in resolved.parents and resolved != site:
                problems.append(f"{where} (outside the site)")
            elif not resolved.is_file():
                problems.append(f"{where} (no such file)")
            elif fragment and resolved.suffix == ".html":
                ids = pages[resolved].ids if resolved in pages else _parse(resolved).ids
                if unquote(fragment) not in ids:
                    problems.append(f"{where} (no anchor #{fragment})")
    return problems


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if len(argv) != 1 or not Path(argv[0]).is_dir():
        print("usage: python docs/check_links.py BUILT_HTML_DIR (e.g. docs/_build/html)", file=sys.stderr)
        return 2
    problems = broken_links(Path(argv[0]))
    for problem in problems:
        print(problem)
    print(f"check_links: {len(problems)} broken internal links", file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
