"""The README and docs/: a newcomer's two minutes, and the rest one link away — every link resolving, every
Python block run as written, every command a block shows accepted by the command line (parsed, not run)."""
import re
import shlex
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
DOCS = sorted((ROOT / "docs").glob("*.md"))
PAGES = [README, *DOCS]
MAX_LINES, MAX_BYTES, MAX_LINE = 150, 16_000, 400
FENCE = re.compile(r"^```(\w*)\n(.*?)^```", re.M | re.S)
LINK = re.compile(r"\]\(([^)\s]+)\)")
DATED = re.compile(r"\b20\d\d-\d\d-\d\d\b|\bbefore:|\bsince then\b|\bOn 20\d\d\b", re.I)


def blocks(path: Path, language: str) -> list[str]:
    return [code for lang, code in FENCE.findall(path.read_text(encoding="utf-8")) if lang == language]


def links(path: Path) -> list[str]:
    return [t for t in LINK.findall(path.read_text(encoding="utf-8")) if not re.match(r"[a-z]+://|#|mailto:", t)]


def test_the_readme_is_a_newcomers_two_minutes():
    text = README.read_text(encoding="utf-8")
    lines = text.splitlines()
    assert len(lines) <= MAX_LINES, f"README.md has {len(lines)} lines (at most {MAX_LINES}: the rest goes to docs/)"
    assert len(text.encode()) <= MAX_BYTES, f"README.md is {len(text.encode())} bytes (at most {MAX_BYTES})"
    long = [i + 1 for i, line in enumerate(lines) if len(line) > MAX_LINE]
    assert not long, f"README.md lines over {MAX_LINE} characters: {long}"
    dated = DATED.findall(text)
    assert not dated, f"README.md holds dated measurements or their history ({dated}): docs/performance.md"


def test_the_readme_links_at_least_three_pages_of_docs():
    linked = {(README.parent / t.split("#")[0]).resolve() for t in links(README)}
    pages = [p for p in DOCS if p.resolve() in linked]
    assert len(pages) >= 3 and len(pages) == len(DOCS), (
        f"docs/ pages not linked from the README: {[p.name for p in DOCS if p.resolve() not in linked]}")


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.name)
def test_every_link_resolves(page):
    missing = [t for t in links(page) if not (page.parent / t.split("#")[0]).exists()]
    assert not missing, f"{page.relative_to(ROOT)} links to missing files: {missing}"


def test_the_link_check_can_fail(tmp_path):
    page = tmp_path / "p.md"
    page.write_text("[a](gone.md) [b](https://example.org) [c](#top)\n", encoding="utf-8")
    assert links(page) == ["gone.md"]


@pytest.mark.parametrize("page", [p for p in PAGES if blocks(p, "python")], ids=lambda p: p.name)
def test_every_python_block_runs(page, tmp_path, monkeypatch):
    """The page's Python blocks, in order, in one namespace (a later block may use an earlier one's names)."""
    monkeypatch.chdir(tmp_path)
    namespace = {"__name__": "__docs__"}
    for i, code in enumerate(blocks(page, "python")):
        exec(compile(code, f"{page.name}, block {i + 1}", "exec"), namespace)


def commands(page: Path) -> list[list[str]]:
    """The `python -m rbcourse …` commands of the page's bash blocks, as argument lists (comments dropped)."""
    found = []
    for code in blocks(page, "bash"):
        for line in code.splitlines():
            for part in line.split("&&"):
                words = shlex.split(part, comments=True)
                if "rbcourse" in words and words.index("rbcourse") > 0 and words[words.index("rbcourse") - 1] == "-m":
                    found.append(words[words.index("rbcourse") + 1:])
    return found


@pytest.mark.parametrize("page", [p for p in PAGES if commands(p)], ids=lambda p: p.name)
def test_every_command_shown_is_accepted(page):
    from rbcourse.__main__ import _parser
    parser, commands_by_name = _parser()
    for argv in commands(page):
        args, extra = parser.parse_known_args(argv)
        assert not extra, f"{page.name}: `python -m rbcourse {' '.join(argv)}`: unrecognized {extra}"


def test_the_command_check_can_fail():
    from rbcourse.__main__ import _parser
    parser, _ = _parser()
    with pytest.raises(SystemExit):
        parser.parse_args(["demo", "no_such_scene"])
