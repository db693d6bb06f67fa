#!/usr/bin/env python3
"""Relative links in Markdown files that point at nothing (python3 only).

Usage: doc_links.py [ROOT] | --self-test
Reads every *.md file git tracks under ROOT (default: the repository holding
this script; outside a git checkout, every *.md but in build*/ and hidden folders) and each inline link or image `[text](target)` whose target is
a relative path (not `http:`, `mailto:` or another scheme, not a bare
`#anchor`). Code spans and fenced code blocks are left out. A target is
resolved against the file's own folder, with any `#anchor` cut off. Prints
`file:line: target (resolves to PATH, which does not exist)` for each one
that names no file or folder, and exits 1 if there is any, 0 if none, 2 on
bad arguments.
--self-test checks the parser on a snippet (links, images, anchors, schemes,
code spans, fenced blocks).
"""
import os
import re
import subprocess
import sys

LINK = re.compile(r"!?\[[^\]]*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
SCHEME = re.compile(r"^[A-Za-z][A-Za-z0-9+.-]*:")
FENCE = re.compile(r"^\s*(```|~~~)")
CODE_SPAN = re.compile(r"`+[^`]*`+")


def link_targets(text):
    """(line number, target) of every relative link outside code."""
    out = []
    fenced = False
    for number, line in enumerate(text.splitlines(), 1):
        if FENCE.match(line):
            fenced = not fenced
            continue
        if fenced:
            continue
        for m in LINK.finditer(CODE_SPAN.sub("", line)):
            target = m.group(1)
            if SCHEME.match(target) or target.startswith("#"):
                continue
            out.append((number, target))
    return out


def markdown_files(root):
    """The *.md files git tracks under root; outside a git checkout, those
    under root but for build*/, node_modules/ and hidden folders."""
    try:
        return subprocess.run(["git", "-C", root, "ls-files", "*.md"], check=True,
                              capture_output=True, text=True).stdout.split()
    except (OSError, subprocess.CalledProcessError):
        pass
    files = []
    for folder, dirs, names in os.walk(root):
        dirs[:] = sorted(d for d in dirs if not (d.startswith(".") or d.startswith("build") or
                                                 d == "node_modules"))
        files += [os.path.relpath(os.path.join(folder, n), root) for n in sorted(names)
                  if n.endswith(".md")]
    return files


def broken_links(root, files):
    found = []
    for rel in files:
        with open(os.path.join(root, rel), encoding="utf-8", errors="replace") as f:
            text = f.read()
        for number, target in link_targets(text):
            path = target.split("#", 1)[0]
            resolved = os.path.normpath(os.path.join(os.path.dirname(rel), path))
            if not os.path.exists(os.path.join(root, resolved)):
                found.append("%s:%d: %s (resolves to %s, which does not exist)" %
                              (rel, number, target, resolved))
    return found


SELF_TEST = """# Title
See [the notes](notes/a.md), [a section](notes/a.md#part) and ![a picture](pic.png).
A [site](https://example.org/x.md), [mail](mailto:a@b.c), [here](#title).
Code: `[not a link](missing.md)`.
```
[not a link either](missing2.md)
```
[gone](gone.md) and [titled](notes/a.md "title")
"""


def self_test():
    got = link_targets(SELF_TEST)
    want = [(2, "notes/a.md"), (2, "notes/a.md#part"), (2, "pic.png"), (8, "gone.md"),
            (8, "notes/a.md")]
    if got != want:
        print("doc_links.py self-test: expected %r, got %r" % (want, got), file=sys.stderr)
        return 1
    return 0


def main(argv):
    if argv == ["--self-test"]:
        return self_test()
    if len(argv) > 1 or (argv and argv[0].startswith("-")):
        print(__doc__.strip().splitlines()[2], file=sys.stderr)
        return 2
    root = argv[0] if argv else os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    if not os.path.isdir(root):
        print("doc_links.py: %s is not a folder" % root, file=sys.stderr)
        return 2
    found = broken_links(root, markdown_files(root))
    for line in found:
        print(line)
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
