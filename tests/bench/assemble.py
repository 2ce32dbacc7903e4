"""Assemble docs/benchmarks.md from the pages the benchmarks wrote (docs/bench/*.md), in a fixed order.

    python tests/bench/assemble.py          (the last step of ``make bench``)

Each page begins with the line its benchmark wrote naming the script, the
machine, Blender and the commit, so every figure in docs/ can be traced to the
run that printed it; this script only orders the pages and adds a contents list, after the
one-screen summary of docs/benchmark-summary.md (written by hand; the docs
test holds each of its figures to the page it links to).
"""

import pathlib
import re

ROOT = pathlib.Path(__file__).resolve().parents[2]
PAGES = ROOT / "docs" / "bench"
#: The order of the pages; any other page follows, by name.
ORDER = ["bench_meshes", "report", "bench_fixed_cost", "bench_atlas", "bench_rays", "bench_million", "bench_held_memory",
         "bench_texel_proxy", "bench_proxy_cells", "bench_clustering", "bench_assets", "bench_buried",
         "bench_concave", "bench_blotch", "bench_adaptive", "bench_weighted", "bench_conventions", "bench_memory",
         "bench_occluders", "bench_objects", "bench_batch", "bench_cycles_margin"]


def anchor(title):
    """GitHub's anchor for a heading."""
    return re.sub(r"[^\w\- ]", "", title.lower()).strip().replace(" ", "-")


def main():
    found = {path.stem: path for path in PAGES.glob("*.md")}
    names = [n for n in ORDER if n in found] + sorted(set(found) - set(ORDER))
    pages = [found[name].read_text() for name in names]
    titles = [page.splitlines()[0].lstrip("# ").strip() for page in pages]
    lines = ["# Benchmarks", "",
             "*Assembled by `tests/bench/assemble.py` from the pages the benchmarks in `tests/bench/` wrote into "
             "`docs/bench/` (`make bench` runs them all, `make bench BENCHES=\"report bench_rays\"` some). Each "
             "section names the command, machine, Blender and commit that wrote it. Do not edit.*", ""]
    summary = (ROOT / "docs" / "benchmark-summary.md").read_text().splitlines()[1:]     # hand-written, checked
    lines += ["## In one screen"] + [re.sub(r"\]\(bench/", "](bench/", line) for line in summary] + [""]
    lines += ["- [{}](#{})".format(title, anchor(title)) for title in titles] + [""]
    for page in pages:
        lines.append(re.sub(r"\]\((?!http)([^)]+\.png)\)", r"](bench/\1)", page).rstrip())
        lines.append("")
    (ROOT / "docs" / "benchmarks.md").write_text("\n".join(lines))
    print("wrote docs/benchmarks.md from {} pages".format(len(pages)))


if __name__ == "__main__":
    main()
