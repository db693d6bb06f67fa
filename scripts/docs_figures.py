#!/usr/bin/env python3
"""docs/api.md's figures, from real runs.

The page quotes examples/embed_headless's output (quads, holes and PSNR per
frame, the median and minimum PSNR), names the frames that carry a
keyframe's cost, gives the keyframe spacing and PSNR of cameras fed one at a
time on the indoor scene's default path (tests/docs/free_camera_figures.cpp)
and the GLFW example's length in lines. This script runs both programs (built
in the project as `example_embed_headless` and `docs_free_camera`, found in
BIN_DIR) and either rewrites those figures in docs/api.md or, with --check,
exits 1 naming every figure that differs (the CTest cli.docs_figures).
Times and the GL renderer's name vary with the machine and are not
compared; the frames do not vary.

Usage: docs_figures.py [--check] BIN_DIR [SOURCE_DIR]
"""
import os
import re
import subprocess
import sys

MARKER = "<!-- output of examples/embed_headless, written by scripts/docs_figures.py -->"
FRAME = re.compile(r"^frame +(\d+) +(keyframe|warped) ")
MS = re.compile(r" +[0-9.]+ ms ")
FREE = re.compile(r"^free camera: indoor, (\d+) frames (\d+)x(\d+), \d+ keyframes built, "
                  r"one every ([0-9.]+) frames, warped \d+, PSNR median ([0-9.]+) dB$")
# The sentence on the page; the numbers are groups 1-5, as FREE's.
FREE_DOC = re.compile(r"On the indoor\s+scene's default path \((\d+) frames, (\d+)x(\d+), default\s+"
                      r"options\) that is one\s+keyframe every ([0-9.]+) frames at ([0-9.]+) dB median")


def fail(msg):
    sys.exit("docs_figures: " + msg)


def run(exe):
    env = dict(os.environ, LP_NUM_THREADS=os.environ.get("LP_NUM_THREADS", "2"))
    if not os.access(exe, os.X_OK):
        fail(f"{exe}: no such program (build the targets example_embed_headless and docs_free_camera)")
    p = subprocess.run([exe], capture_output=True, text=True, env=env, timeout=300)
    if p.returncode != 0:
        fail(f"{exe} exited {p.returncode}: {p.stderr.strip() or p.stdout.strip()[-300:]}")
    return p.stdout.splitlines()


def quoted(lines):
    """What the page shows: the first line, frames 0 to 10, "...", the last
    two frames and the closing line."""
    frames = [l for l in lines if FRAME.match(l)]
    if len(lines) < 3 or len(frames) < 13 or not lines[-1].startswith("in-between frames:"):
        fail("unexpected output of the example:\n" + "\n".join(lines))
    head = [l for l in frames if int(FRAME.match(l).group(1)) <= 10]
    return [lines[0]] + head + ["..."] + frames[-2:] + [lines[-1]]


def cost_frames(lines):
    """The frames that build a keyframe: the first warped frame after each
    of the first two keyframe frames (a keyframe is built when first needed)."""
    out, after_key = [], False
    for l in lines:
        m = FRAME.match(l)
        if not m:
            continue
        if m.group(2) == "keyframe":
            after_key = True
        elif after_key:
            out.append(int(m.group(1)))
            after_key = False
        if len(out) == 2:
            break
    return out


def comparable(line):
    """A quoted line without what varies with the machine."""
    line = MS.sub(" <ms> ", line)
    return re.sub(r"^(.*: \d+ triangles), .*$", r"\1, <renderer>", line)


def main():
    args = sys.argv[1:]
    check = "--check" in args
    args = [a for a in args if a != "--check"]
    if not 1 <= len(args) <= 2:
        sys.exit(__doc__.split("\n\n")[-1].strip())
    bindir = args[0]
    src = args[1] if len(args) == 2 else os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    doc_path = os.path.join(src, "docs", "api.md")
    doc = open(doc_path, encoding="utf-8").read()
    lines = run(os.path.join(bindir, "example_embed_headless"))
    free = run(os.path.join(bindir, "docs_free_camera"))
    free_m = FREE.match(free[-1] if free else "")
    if not free_m:
        fail("unexpected output of docs_free_camera:\n" + "\n".join(free))
    free_now = free_m.groups()

    # The output block after the marker.
    block = re.search(re.escape(MARKER) + r"\n```\n(.*?)\n```\n", doc, re.S)
    if not block:
        fail(f"{doc_path}: no ``` block after the line '{MARKER}'")
    want = quoted(lines)
    # The frames that carry a keyframe's cost, named in the paragraph below it.
    cost = cost_frames(lines)
    cost_re = re.compile(r"carries its cost \(frames (\d+) and (\d+) here\)")
    # The GLFW example's length.
    glfw = os.path.join(src, "examples", "embed_glfw", "main.cpp")
    glfw_lines = sum(1 for _ in open(glfw, encoding="utf-8"))
    glfw_re = re.compile(r"`examples/embed_glfw/main\.cpp` \((\d+) lines\)")
    for name, rx in (("cost frames", cost_re), ("GLFW example length", glfw_re),
                     ("free camera", FREE_DOC)):
        if not rx.search(doc):
            fail(f"{doc_path}: the {name} sentence ({rx.pattern}) is not there")

    if not check:
        doc = doc[: block.start(1)] + "\n".join(want) + doc[block.end(1):]
        doc = cost_re.sub(f"carries its cost (frames {cost[0]} and {cost[1]} here)", doc)
        doc = glfw_re.sub(f"`examples/embed_glfw/main.cpp` ({glfw_lines} lines)", doc)
        m = FREE_DOC.search(doc)
        parts, last = [], m.start()
        for g, value in enumerate(free_now, 1):
            parts += [doc[last:m.start(g)], value]
            last = m.end(g)
        doc = doc[: m.start()] + "".join(parts) + doc[last:]
        open(doc_path, "w", encoding="utf-8").write(doc)
        print(f"docs_figures: wrote {doc_path} ({want[-1]})")
        return 0

    bad = []
    have = block.group(1).split("\n")
    if len(have) != len(want):
        bad.append(f"the output block has {len(have)} lines, the example gives {len(want)}")
    for h, w in zip(have, want):
        if comparable(h) != comparable(w):
            bad.append(f"  docs/api.md: {h}\n  the example: {w}")
    got = [int(x) for x in cost_re.search(doc).groups()]
    if got != cost:
        bad.append(f"the frames that carry a keyframe's cost: the page says {got}, the example {cost}")
    got = int(glfw_re.search(doc).group(1))
    if got != glfw_lines:
        bad.append(f"examples/embed_glfw/main.cpp: the page says {got} lines, it has {glfw_lines}")
    got = FREE_DOC.search(doc).groups()
    if got != free_now:
        bad.append(f"cameras fed one at a time (frames, width, height, frames per keyframe, "
                   f"PSNR median): the page says {got}, the program {free_now}")
    if bad:
        print("docs/api.md disagrees with what the code produces (regenerate: "
              "python3 scripts/docs_figures.py build/bin):")
        print("\n".join(bad))
        return 1
    print(f"docs_figures: docs/api.md agrees with the programs ({len(want)} lines; {want[-1]}; "
          f"{free[-1]})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
