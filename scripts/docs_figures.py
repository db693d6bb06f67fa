#!/usr/bin/env python3
"""The figures docs/api.md and README.md quote, from real runs.

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

It also checks (and rewrites) the figures README.md quotes from commands:
the quad count of `hybridwalk lod --scene indoor --frame 0` and frame 5's
PSNR in the overview's caption, and the published size of the indoor walk;
rewriting, it draws docs/images/overview.png again from the same runs.

Usage: docs_figures.py [--check] BIN_DIR [SOURCE_DIR]
"""
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

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


def set_groups(text, rx, values):
    """TEXT with the groups of RX's first match replaced by VALUES."""
    m = rx.search(text)
    parts, last = [], m.start()
    for g, value in enumerate(values, 1):
        parts += [text[last:m.start(g)], value]
        last = m.end(g)
    return text[: m.start()] + "".join(parts) + text[last:]


# The README's figures: the overview's caption (the quad count of `lod`,
# frame 5's PSNR) and the published size of the indoor walk.
README_LOD = re.compile(r"\(`hybridwalk lod --scene indoor --frame 0`\):\s+([0-9,]+) quads")
README_FRAME5 = re.compile(r"`hybridwalk walk --scene indoor --mode hybrid --save-frames`\),\s+not\s+"
                           r"rendered\s+but\s+warped\s+from\s+keyframes\s+0\s+and\s+10:\s+([0-9.]+) dB")
README_PUBLISH = re.compile(r"--out out/site/indoor +# ([0-9.]+) MB for the 120-frame indoor walk")


def readme_figures(hw, work):
    """Runs the commands the README quotes; (figures, overview picture parts)."""
    def go(*args):
        env = dict(os.environ, LP_NUM_THREADS=os.environ.get("LP_NUM_THREADS", "2"))
        p = subprocess.run([hw, *args], capture_output=True, text=True, env=env, timeout=300)
        if p.returncode != 0:
            fail(f"hybridwalk {' '.join(args)} exited {p.returncode}: {p.stderr.strip()[-300:]}")
        return p.stdout
    lod = os.path.join(work, "lod.png")
    m = re.search(r"^(\d+) quads", go("lod", "--scene", "indoor", "--frame", "0", "--out", lod), re.M)
    if not m:
        fail("hybridwalk lod printed no quad count")
    quads = f"{int(m.group(1)):,}"
    walk = os.path.join(work, "walk")
    # Frame 5 lies between keyframes 0 and 10: the first 11 frames give it.
    go("walk", "--scene", "indoor", "--mode", "hybrid", "--save-frames", "--frames", "11",
       "--strips", "0", "--quiet", "--out", walk)
    f5 = json.load(open(os.path.join(walk, "report.json")))["frames"][5]
    if f5.get("keyframes") != [0, 10] or f5.get("psnr") is None:
        fail(f"frame 5 of the indoor walk is not warped from keyframes 0 and 10: {f5.get('keyframes')}")
    db, site = os.path.join(work, "db"), os.path.join(work, "site")
    go("bake", "--scene", "indoor", "--quiet", "--out", db)
    m = re.search(r" ([0-9.]+) MB in ", go("publish", "--keyframes", db, "--out", site))
    if not m:
        fail("hybridwalk publish printed no size")
    figures = {README_LOD: (quads,), README_FRAME5: (f"{f5['psnr']:.1f}",),
               README_PUBLISH: (m.group(1),)}
    return figures, (lod, os.path.join(walk, "frames", "0005.png"))


def write_overview(path, left, right):
    """docs/images/overview.png: the two pictures side by side, 8 white pixels
    apart (pngquant, when installed, makes it small)."""
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import contact_sheet
    (wl, h, bl, rl), (wr, hr, br, rr) = contact_sheet.read_png(left), contact_sheet.read_png(right)
    if h != hr:
        fail(f"{left} and {right} differ in height")
    gap = 8

    def rgb(src, w, bpp):
        return b"".join(src[x * bpp:x * bpp + 3] for x in range(w))
    rows = [rgb(rl[y], wl, bl) + b"\xff" * (3 * gap) + rgb(rr[y], wr, br) for y in range(h)]
    contact_sheet.write_png(path, wl + gap + wr, h, rows)
    if shutil.which("pngquant"):
        subprocess.run(["pngquant", "--force", "--speed", "1", "--output", path, "64", path],
                       check=False)


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
    readme_path = os.path.join(src, "README.md")
    readme = open(readme_path, encoding="utf-8").read()
    for rx in (README_LOD, README_FRAME5, README_PUBLISH):
        if not rx.search(readme):
            fail(f"{readme_path}: no text matching {rx.pattern}")
    with tempfile.TemporaryDirectory() as work:
        readme_now, overview = readme_figures(os.path.join(bindir, "hybridwalk"), work)
        return compare_or_write(check, src, doc_path, doc, lines, free, free_now, readme_path,
                                readme, readme_now, overview)


def compare_or_write(check, src, doc_path, doc, lines, free, free_now, readme_path, readme,
                     readme_now, overview):

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
        # A line that differs only in what varies with the machine is kept.
        have = block.group(1).split("\n")
        if len(have) == len(want):
            want = [h if comparable(h) == comparable(w) else w for h, w in zip(have, want)]
        doc = doc[: block.start(1)] + "\n".join(want) + doc[block.end(1):]
        doc = cost_re.sub(f"carries its cost (frames {cost[0]} and {cost[1]} here)", doc)
        doc = glfw_re.sub(f"`examples/embed_glfw/main.cpp` ({glfw_lines} lines)", doc)
        doc = set_groups(doc, FREE_DOC, free_now)
        open(doc_path, "w", encoding="utf-8").write(doc)
        for rx, values in readme_now.items():
            readme = set_groups(readme, rx, values)
        open(readme_path, "w", encoding="utf-8").write(readme)
        write_overview(os.path.join(src, "docs", "images", "overview.png"), *overview)
        print(f"docs_figures: wrote {doc_path}, {readme_path} and docs/images/overview.png "
              f"({want[-1]})")
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
    for rx, values in readme_now.items():
        got = rx.search(readme).groups()
        if got != values:
            bad.append(f"README.md: '{rx.search(readme).group(0)}' gives {got}, the program {values}")
    got = FREE_DOC.search(doc).groups()
    if got != free_now:
        bad.append(f"cameras fed one at a time (frames, width, height, frames per keyframe, "
                   f"PSNR median): the page says {got}, the program {free_now}")
    if bad:
        print("docs/api.md or README.md disagrees with what the code produces (regenerate: "
              "python3 scripts/docs_figures.py build/bin):")
        print("\n".join(bad))
        return 1
    print(f"docs_figures: docs/api.md agrees with the programs ({len(want)} lines; {want[-1]}; "
          f"{free[-1]})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
