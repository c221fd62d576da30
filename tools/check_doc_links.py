#!/usr/bin/python3
"""Checks the Markdown links of README.md and docs/*.md: every relative link names a file that exists and every
#anchor a heading of that file (GitHub's rule: lower case, punctuation dropped, spaces to '-'). CTest runs it
(Docs.EveryLinkAndAnchorResolves); tests/architecture/docs_test.cpp checks the README's results against docs/results.md.
Run from the checkout: /usr/bin/python3 tools/check_doc_links.py; exit status 1 and one line per broken link."""
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LINK = re.compile(r"(?<!!)\[[^\]]*\]\(([^)\s]+)\)|!\[[^\]]*\]\(([^)\s]+)\)")
FENCE = re.compile(r"^(```|~~~)")


def strip_code(text):
    """The text with fenced blocks and inline code removed, so links inside code are not checked."""
    out, fenced = [], False
    for line in text.splitlines():
        if FENCE.match(line.strip()):
            fenced = not fenced
            out.append("")
            continue
        out.append("" if fenced else re.sub(r"`[^`]*`", "", line))
    return "\n".join(out)


def slug(heading):
    s = heading.strip().lower()
    s = re.sub(r"[^\w\- ]", "", s)  # GitHub drops punctuation but keeps letters, digits, '-', '_' and spaces
    return s.replace(" ", "-")


def anchors(path):
    found, counts, fenced = set(), {}, False
    with open(path, encoding="utf-8") as f:
        for line in f:
            if FENCE.match(line.strip()):
                fenced = not fenced
            if fenced:
                continue
            m = re.match(r"^#{1,6}\s+(.*?)\s*#*\s*$", line)
            if m:
                text = re.sub(r"`", "", m.group(1))
                text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", text)
                base = slug(text)
                n = counts.get(base, 0)
                found.add(base if n == 0 else f"{base}-{n}")
                counts[base] = n + 1
    return found


def check_links(files):
    errors = []
    for md in files:
        with open(md, encoding="utf-8") as f:
            text = strip_code(f.read())
        for m in LINK.finditer(text):
            target = m.group(1) or m.group(2)
            if re.match(r"^[a-z]+:", target):
                continue
            path, _, anchor = target.partition("#")
            full = os.path.normpath(os.path.join(os.path.dirname(md), path)) if path else md
            rel = os.path.relpath(md, ROOT)
            if not os.path.exists(full):
                errors.append(f"{rel}: {target}: no such file")
            elif anchor and full.endswith(".md") and anchor not in anchors(full):
                errors.append(f"{rel}: {target}: no heading #{anchor}")
    return errors


def main():
    files = [os.path.join(ROOT, "README.md")]
    docs = os.path.join(ROOT, "docs")
    files += sorted(os.path.join(docs, n) for n in os.listdir(docs) if n.endswith(".md"))
    errors = check_links(files)
    for e in errors:
        print(e)
    print(f"{len(files)} files, {len(errors)} problems")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
