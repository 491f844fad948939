#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""check_links.py ROOT: every relative link and image in ROOT/README.md and
ROOT/docs/*.md names a file that exists, and every #anchor a heading of its
target (GitHub's slugs), outside code. Also: README.md under 300 lines, its
first code block exactly `make demo` and `make test`. Prints each fault as
FILE:LINE: ...; exit 1 if any. A built-in sample with known faults is
checked first, so a checker that finds nothing fails too. (ctest docs.links)
"""
import pathlib
import re
import sys
import tempfile

LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
README_LIMIT = 300


def prose_lines(text, keep_code=False):
    """(line number, line) outside fenced code; inline code removed unless keep_code."""
    fence = None
    for n, line in enumerate(text.splitlines(), 1):
        m = re.match(r"^\s*(```+|~~~+)", line)
        if m:
            if fence is None:
                fence = m.group(1)
            elif m.group(1).startswith(fence):
                fence = None
            continue
        if fence is None:
            yield n, line if keep_code else re.sub(r"(`+)(?:(?!\1).)+?\1", "", line)


def slug(heading):
    """GitHub's anchor for a heading: markup dropped, lower case, punctuation out, spaces to '-'."""
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", heading.strip())
    text = text.replace("`", "").lower()
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors(path):
    seen, out = {}, set()
    for _, line in prose_lines(path.read_text(), keep_code=True):
        m = re.match(r"^#{1,6}\s+(.*?)\s*#*\s*$", line)
        if m:
            s = slug(m.group(1))
            k = seen.get(s, 0)
            seen[s] = k + 1
            out.add(s if k == 0 else "%s-%d" % (s, k))
    return out


def check_file(path, root):
    faults = []
    for n, line in prose_lines(path.read_text()):
        for m in LINK.finditer(line):
            target = m.group(1)
            if re.match(r"^[a-z][a-z0-9+.-]*:", target, re.I):  # http:, https:, mailto: ...
                continue
            file_part, _, anchor = target.partition("#")
            dest = (path.parent / file_part).resolve() if file_part else path.resolve()
            where = "%s:%d: %s" % (path.relative_to(root), n, target)
            if not dest.exists():
                faults.append("%s: no such file" % where)
            elif not dest.resolve().is_relative_to(root.resolve()):
                faults.append("%s: outside the repository" % where)
            elif anchor:
                if dest.suffix != ".md":
                    faults.append("%s: an anchor into a file that is not Markdown" % where)
                elif anchor not in anchors(dest):
                    faults.append("%s: no heading with anchor '%s' in %s" % (where, anchor, dest.name))
    return faults


def check_readme(readme, root):
    faults = []
    lines = readme.read_text().splitlines()
    if len(lines) >= README_LIMIT:
        faults.append("%s: %d lines, the limit is under %d" % (readme.relative_to(root), len(lines), README_LIMIT))
    fences = [i for i, l in enumerate(lines) if l.startswith("```")]
    first = [l.split("#")[0].strip() for l in lines[fences[0] + 1:fences[1]]] if len(fences) >= 2 else []
    if first != ["make demo", "make test"]:
        faults.append("%s: the first code block is %s, not `make demo` and `make test`" % (readme.relative_to(root), first))
    return faults


def check_tree(root):
    files = [root / "README.md"] + sorted((root / "docs").glob("*.md"))
    faults = check_readme(root / "README.md", root)
    for f in files:
        faults += check_file(f, root)
    return files, faults


def self_test():
    """A tree with one fault of each kind, and links that must pass."""
    with tempfile.TemporaryDirectory() as tmp:
        root = pathlib.Path(tmp)
        (root / "docs").mkdir()
        (root / "docs" / "a.md").write_text(
            "# Page A\n\n## Visual review (`--html`)\n\n## Twice\n\n## Twice\n\n"
            "[ok](#visual-review---html) [ok](#twice-1) [ok](../README.md#top) [ok](https://x.org/#y)\n"
            "`[in code](missing.md)`\n```\n[in a fence](missing.md)\n```\n"
            "[bad](#nowhere) [bad](b.md) [bad](../README.md#nope) ![bad](img/none.png)\n")
        (root / "README.md").write_text("# Top\n\n```sh\nmake demo\nmake build\n```\n[bad](docs/a.md#twice-2)\n")
        _, faults = check_tree(root)
        expect = ["README.md: the first code block", "README.md:7: docs/a.md#twice-2",
                  "docs/a.md:14: #nowhere", "docs/a.md:14: b.md", "docs/a.md:14: ../README.md#nope",
                  "docs/a.md:14: img/none.png"]
        got = [f for f in faults]
        missed = [e for e in expect if not any(f.startswith(e) for f in got)]
        extra = [f for f in got if not any(f.startswith(e) for e in expect)]
        if missed or extra:
            sys.exit("check_links.py self-test: missed %s, wrongly flagged %s" % (missed, extra))


def main():
    self_test()
    root = pathlib.Path(sys.argv[1]).resolve()
    files, faults = check_tree(root)
    for f in faults:
        print(f)
    if faults:
        sys.exit(1)
    print("%d files, every relative link and anchor resolves" % len(files))


if __name__ == "__main__":
    main()
