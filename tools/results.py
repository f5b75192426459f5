"""The documentation's results pages, generated from ``exprclone evaluate`` and the benchmarks.

    python tools/results.py evaluate [EVALUATE ARGS...]   # runs exprclone evaluate, keeps its report
    python tools/results.py bench NAME [BENCHMARK ARGS...] # runs benchmarks/NAME.py, keeps what it prints
    python tools/results.py judges [JUDGES ARGS...]        # runs tools/video_judges.py, keeps what it prints
    python tools/results.py split [SPLIT ARGS...]          # runs tools/identity_split.py, keeps what it prints
    python tools/results.py db [DB_TERMS ARGS...]          # runs tools/db_terms.py, keeps what it prints
    python tools/results.py render                         # the pages from what was kept

``evaluate``, ``bench`` and ``judges`` run their command (in this interpreter, from the repository's
root), keep its output under ``docs/results/data/`` with what the pages put at their top
(the command, the data, the date, exprclone's version, the machine, how long it took), and
render the pages. ``render`` writes ``docs/results/evaluation.rst``, ``docs/results/speed.rst``,
``docs/results/video.rst``, ``docs/results/elastic.rst`` and the figure ``docs/results/data/evaluate/scores.png`` from the kept
files alone: the documentation's build reads them and runs nothing.

Example (the run behind the published pages)::

    python tools/results.py evaluate --data ../shared/data/london --pairs 200 --held-out 4 --jobs 2 --retargets true,false
    python tools/results.py bench run --repeat 5 --quick
    python tools/results.py bench video --repeat 3
    python tools/results.py bench serve --scheduler --requests 60
    python tools/results.py judges --jobs 2
    python tools/results.py split --pairs 80 --jobs 2
    python tools/results.py db --data ../shared/data --pairs 300 --held-out 4
    python tools/results.py db --evaluated docs/results/data/evaluate/pairs.csv   # after an evaluate with --retargets true,false
"""

from __future__ import annotations

import csv
import datetime
import json
import os
import platform
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from exprclone.evaluation.runner import NO_RETARGET, marks

ROOT = Path(__file__).resolve().parents[1]
PAGES = ROOT / "docs" / "results"
KEPT = PAGES / "data"
#: a benchmark's flags that make it measure another thing: its output with one is kept apart (``serve-scheduler.txt``).
MODES = ("--scheduler",)
#: the report files of ``exprclone evaluate`` kept for the pages.
REPORT_FILES = ("pairs.csv", "summary.md", "gallery.jpg")


def _meta(command: list[str], data: str, seconds: float) -> dict:
    """What a results page states at its top about the run that made it."""
    from exprclone import __version__

    return {
        "command": " ".join(command),
        "data": data,
        "date": datetime.date.today().isoformat(),
        "version": __version__,
        "machine": f"{os.cpu_count()} cores, {platform.machine()}, Python {platform.python_version()}",
        "seconds": round(seconds, 1),
        "load": f"{os.getloadavg()[0]:.1f} on {os.cpu_count()} cores",
    }


def _run(command: list[str], **kwargs) -> tuple[subprocess.CompletedProcess, float]:
    """Run ``command`` from the repository's root with this interpreter's exprclone; stop if it fails."""
    start = time.perf_counter()
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT / "src"), os.environ.get("PYTHONPATH", "")])}
    done = subprocess.run(command, cwd=ROOT, env=env, text=True, **kwargs)
    if done.returncode:
        sys.exit(f"results: {' '.join(command)} failed with status {done.returncode}")
    return done, time.perf_counter() - start


def _option(args: list[str], name: str, default: str) -> str:
    return args[args.index(name) + 1] if name in args[:-1] else default


def collect_evaluate(args: list[str]) -> None:
    """Run ``exprclone evaluate ARGS`` into a temporary folder; keep its report and the run's facts."""
    with tempfile.TemporaryDirectory() as tmp:
        command = ["exprclone", "evaluate", *args, "--out", tmp]
        _, seconds = _run([sys.executable, "-m", "exprclone", *command[1:]])
        out = KEPT / "evaluate"
        shutil.rmtree(out, ignore_errors=True)
        out.mkdir(parents=True)
        for name in REPORT_FILES:
            if (Path(tmp) / name).exists():
                shutil.copy2(Path(tmp) / name, out / name)
    meta = _meta(["exprclone", "evaluate", *args], _option(args, "--data", "the samples shipped in exprclone.data"), seconds)
    (out / "meta.json").write_text(json.dumps(meta, indent=1) + "\n")


def collect_bench(name: str, args: list[str]) -> None:
    """Run ``benchmarks/NAME.py ARGS``; keep what it prints and the run's facts (apart for each of :data:`MODES` given)."""
    script = ROOT / "benchmarks" / f"{name}.py"
    if not script.exists():
        sys.exit(f"results: no benchmark {name!r} in benchmarks/")
    _collect_printed(script, args, KEPT / "bench", "".join(mode.replace("--", "-") for mode in MODES if mode in args))


def _collect_printed(script: Path, args: list[str], out: Path, suffix: str = "") -> None:
    """Run ``script ARGS``; keep what it prints (``out/NAME[SUFFIX].txt``) and the run's facts (``.json``)."""
    done, seconds = _run([sys.executable, str(script), *args], stdout=subprocess.PIPE)
    out.mkdir(parents=True, exist_ok=True)
    (out / f"{script.stem}{suffix}.txt").write_text(done.stdout)
    meta = _meta(["python", str(script.relative_to(ROOT)), *args], _option(args, "--data", "../shared/data"), seconds)
    (out / f"{script.stem}{suffix}.json").write_text(json.dumps(meta, indent=1) + "\n")


# ---- the pages, from what was kept ------------------------------------------------------------------------------------------


def _facts(meta: dict) -> list[str]:
    """The field list at the top of a results page: how the figures below were made."""
    facts = [
        f":Command: ``{meta['command']}``",
        f":Data: ``{meta['data']}``",
        f":Date: {meta['date']}",
        f":Version: exprclone {meta['version']}",
        f":Machine: {meta['machine']}",
        f":Took: {meta['seconds'] / 60:.1f} minutes",
    ]
    if "load" in meta:
        facts.append(f":Load: {meta['load']} (the machine's load average as the run started: other work shared its cores)")
    return facts + [""]


def _list_table(header: list[str], rows: list[list[str]], widths: str | None = None) -> list[str]:
    if not rows:
        return ["No pairs.", ""]
    lines = [".. list-table::", "   :header-rows: 1", ""]
    if widths:
        lines.insert(2, f"   :widths: {widths}")
    for row in [header, *rows]:
        lines += [f"   * - {row[0]}"] + [f"     - {cell}" for cell in row[1:]]
    return lines + [""]


def _rows(path: Path) -> list[dict]:
    """``pairs.csv`` as :func:`exprclone.evaluation.statistics.summarise` takes it: scores as numbers, failures as booleans."""
    numbers = ("target_smile", "overall", "mouth", "eyes_brows", "identity", "teeth", "source_teeth")
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    for row in rows:
        row["failed"] = row["failed"] not in ("", "False")
        for key in numbers:
            row[key] = float(row[key]) if row[key] not in ("", None) else float("nan")
    return rows


def _summary_table(summary: list[dict]) -> list[str]:
    from exprclone.evaluation.report import cells

    header = ["method", "pairs", "failed", "landmark error, mean / median", "mouth, mean / median", "mouth minus global, paired"]
    header += ["eyes and brows, mean / median", "identity, mean / median", "same person", "identity beyond a real smile as wide"]
    header += ["teeth: source shows", "teeth: source shows none"]
    header += ["judged smiling", "shadow warmth, median [95% interval]", "grey shadows"]
    return _list_table(header, [[f"``{s['method']}``", *cells(s)] for s in summary])


def _blendshape_table(summary: list[dict]) -> list[str]:
    from exprclone.evaluation.report import BLENDSHAPE_HEADER, blendshape_cells

    return _list_table(["method", *BLENDSHAPE_HEADER], [[f"``{s['method']}``", *blendshape_cells(s)] for s in summary])


def _contrast_table(lines: list[dict]) -> list[str]:
    header = ["compared, pair by pair", "pairs", "mouth", "landmarks overall", "eyes and brows", "identity"]
    keys = ("mouth", "overall", "eyes_brows", "identity")
    rows = [[f"``{c['compared']}``", str(c["pairs"])] + [f"{c[k + '_mean']:+.4f} ± {c[k + '_se']:.4f}" for k in keys] for c in lines]
    return _list_table(header, rows)


def _scores_figure(summaries: dict[str, list[dict]], out: Path) -> None:
    """Mouth error and identity distance per method, over all pairs and over the broad smiles."""
    import matplotlib

    matplotlib.use("agg")
    import matplotlib.pyplot as plt
    import numpy as np

    fig, axes = plt.subplots(1, 2, figsize=(11, 0.32 * len(next(iter(summaries.values()))) + 1.2), sharey=True)
    for ax, key, label in zip(axes, ("mouth", "identity"), ("mouth landmark error (mean)", "identity distance to the target (mean)")):
        for offset, (name, summary) in zip((-0.2, 0.2), summaries.items()):
            y = np.arange(len(summary)) + offset
            ax.barh(y, [s[f"{key}_mean"] for s in summary], height=0.4, label=name)
        ax.set_xlabel(label)
    axes[0].set_yticks(range(len(summary)), [s["method"] for s in summary])
    axes[0].invert_yaxis()
    axes[0].legend(loc="lower right")
    fig.tight_layout()
    fig.savefig(out, dpi=100)
    plt.close(fig)


def render_evaluation() -> str | None:
    """``evaluation.rst`` from the kept report; the README's headline table (Markdown)."""
    from exprclone.evaluation.report import alike
    from exprclone.evaluation.statistics import STRONG_SMILE, contrasts, summarise

    kept = KEPT / "evaluate"
    if not (kept / "pairs.csv").exists():
        return None
    meta = json.loads((kept / "meta.json").read_text())
    rows = _rows(kept / "pairs.csv")
    summaries = {
        "all pairs": summarise(rows),
        f"broad smiles (mouth widens by {STRONG_SMILE:.0%} or more)": summarise(rows, strong_only=True),
    }
    _scores_figure(summaries, kept / "scores.png")
    n_pairs = len({(r["source"], r["target"]) for r in rows})
    n_broad = len({(r["source"], r["target"]) for r in rows if r["target_smile"] >= STRONG_SMILE})
    text = ["..", "   Generated by tools/results.py from docs/results/data/evaluate/: do not edit.", "", "Scores against real smiles"]
    text += ["=" * len(text[-1]), ""] + _facts(meta)
    text += [
        f"Each person's smile is cloned onto another person's neutral photo ({n_pairs} ordered pairs of different people",
        "with a fixed seed), by every method, and each result is scored against the target's *own* real smile:",
        "",
        "- **landmark error**: the 68 landmarks detected on the result against those of the real smile, after a similarity",
        "  alignment, in outer-eye-corner distances; overall, the mouth, the eyes and brows;",
        "- **mouth minus global, paired**: the method's mouth error minus global warping's on the same pair (in the same",
        "  variant), with its standard error;",
        "- **identity**: dlib's face-descriptor distance to the target's neutral photo (the same person below 0.6), and its",
        "  excess over a real smile as wide: the line of identity against the mouth's widening fitted on the targets' own",
        "  real smiles, each result's distance above it (its mean, with a bootstrap interval; a clone that smiled less",
        "  would not gain there);",
        "- **teeth**: of the pairs whose source's smile shows teeth, the share of results that show teeth; of the others,",
        "  the share that show teeth all the same;",
        "- **judged smiling**: the share of results that an expression judge (a classifier on the landmarks, trained",
        "  without the pair's two people) calls smiling;",
        "- **shadow warmth**: over the skin that darkens by more than 6 L* from the target's neutral photo, the median of",
        "  (C*/C*_neutral) / (L*/L*_neutral): 1 for a shading that dims R, G and B alike, more for real skin's warmer",
        "  shadows (:doc:`../explanation/fidelity`); its median over the results with such skin, with a bootstrap interval,",
        "  and the share of them under 1.08 (grey shadows). The methods without ERI shade nothing: the few results in",
        "  which they darken enough skin to be measured are those whose warp and the neutral photo's warp onto the result's",
        "  landmarks do not line up, so their figure is not a shadow's colour;",
        "- **the blendshape judge** (:doc:`../explanation/expression-judge`), in a table of its own under each: MediaPipe's",
        "  52 expression scores read on the result; their distance to the source's expression photo's per region (mouth,",
        "  eyes, brows) and in total, and to the target's real expression's; the distance between the result's change from",
        "  the target's neutral photo and the source's change from its own (the motion alone, as people's faces differ at",
        "  rest; means, with 95% bootstrap intervals over the pairs); and the source's rise kept: over the four scores the",
        "  source raises most from its neutral photo, the result's rise from the target's neutral photo over the source's",
        "  (median, with its interval);",
        "- ``no change`` (the neutral photo as the result) and ``real`` (the real smile) are the floor and the ceiling.",
        "",
        *[line for sentence in alike(rows) for line in (sentence, "")],
        *_variants_said(rows),
        ".. figure:: data/evaluate/scores.png",
        "   :alt: mouth error and identity distance per method",
        "   :width: 100%",
        "",
        "   Mean mouth error and identity distance of each method, over all pairs and over the broad smiles.",
        "",
        "All pairs",
        "---------",
        "",
        *_summary_table(summaries["all pairs"]),
        "The blendshape judge, all pairs:",
        "",
        *_blendshape_table(summaries["all pairs"]),
        "Broad smiles",
        "------------",
        "",
        f"The {n_broad} pairs whose target smiles broadly: its mouth widens by {STRONG_SMILE:.0%} or more between its two photos.",
        "A real smile is a better ground truth for a broad cloned one than a subtle smile is.",
        "",
        *_summary_table(list(summaries.values())[1]),
        "The blendshape judge, broad smiles:",
        "",
        *_blendshape_table(list(summaries.values())[1]),
    ]
    if contrasts(rows):
        text += ["Pair by pair", "------------", "", "Mean difference over the pairs, with its standard error; below 0, the first is"]
        text += ["closer to the real smile (for identity, to the target's own face). All pairs, then the broad smiles.", ""]
        text += _contrast_table(contrasts(rows)) + _contrast_table(contrasts(rows, strong_only=True))
    if (kept / "gallery.jpg").exists():
        text += [
            "Gallery",
            "-------",
            "",
            ".. figure:: data/evaluate/gallery.jpg",
            "   :alt: best, median and worst pairs",
            "   :width: 100%",
            "",
        ]
        text += ["   E+MD's best, median and worst pairs by mouth error, and the median pair whose source shows teeth: the source's"]
        text += ["   smile, the target's neutral photo, the result, the target's real smile, and their mouths close up.", ""]
    (PAGES / "evaluation.rst").write_text("\n".join(text + _split_section()))
    return _headline(summaries, meta)


def _split_section() -> list[str]:
    """The identity split (``tools/identity_split.py``) as kept, under the scores: where a clone stops looking like its
    target, its shape's part and its shading's."""
    output = KEPT / "split" / "identity_split.txt"
    if not output.exists():
        return []
    text = ["", "Where a clone stops looking like its target", "-------------------------------------------", ""]
    text += _facts(json.loads(output.with_suffix(".json").read_text()))
    text += [
        "Each result's identity distance against a real smile *as wide as itself* (the line over the targets' own real",
        "smiles), on pairs held out from what the clones learnt: the clone as made (``e+md``), the source's motion without",
        "shading (``global``), the target's own real smile's landmarks given as GI with the source's shading and teeth, without",
        "the teeth, and without shading, and each target's own smile cloned onto itself (``self``); the excess's mean with a",
        "95% bootstrap interval (the rows of ``../shared/notes/identity.md``).",
        "",
        "::",
        "",
    ]
    return text + ["   " + line if line.strip() else "" for line in output.read_text().splitlines()] + [""]


def render_elastic() -> None:
    """``elastic.rst``: when the elastic model acts with the paper's stages, as ``tools/db_terms.py`` printed it: the DB
    metric's choice and its terms over London pairs, and (``--evaluated``) the elastic model against GI on them."""
    text = ["..", "   Generated by tools/results.py from docs/results/data/db/: do not edit.", ""]
    text += ["When the elastic model acts", "=" * 27, ""]
    text += [
        "With the paper's stages (``retarget`` off), the DB metric (Eq. 7) chooses the elastic model's lambda_k between",
        "global warping (lambda_k 0, GI) and local re-shaping (LI); :doc:`../explanation/choices` says how the metric is",
        "read. With this project's default (``retarget`` on) LI is GI, and there is nothing to balance. What follows is",
        "what ``tools/db_terms.py`` printed, its terms explained in its own notes: on how many pairs the metric picks",
        "lambda_k above 0, and why it does not on the others (a first step from GI towards LI lowers DB only when LI lies",
        "towards the source's expression in face space by a cosine above ``needed``).",
        "",
    ]
    text += _printed(KEPT / "db") or ["Not measured yet: ``python tools/results.py db``.", ""]
    (PAGES / "elastic.rst").write_text("\n".join(text))


#: what each word of a variant's mark on a row means (:func:`exprclone.evaluation.runner.variant_label`).
VARIANTS = {
    "rbf": "run on the RBF transfer's global warp (the paper's Figs. 19-20) instead of the similarity transfer;"
    " :doc:`../explanation/global-warps` discusses them.",
    NO_RETARGET: "run the paper's stages (``--no-retarget``): the source's motion as it is, local re-shaping and the"
    " DB metric's lambda_k as the paper has them; the rows without it, this project's default, make the source's"
    " expression as the target's own face makes it (:doc:`../explanation/fidelity`).",
}


def _variants_said(rows: list[dict]) -> list[str]:
    """A sentence for each word of the variants' marks found on the rows (:data:`VARIANTS`)."""
    found = set().union(*(marks(row.get("variant", "")) for row in rows))
    return [line for word, said in VARIANTS.items() if word in found for line in (f"Rows whose mark holds ``{word}`` {said}", "")]


def _headline(summaries: dict[str, list[dict]], meta: dict) -> str:
    """The README's small table: the default setting's main methods, all pairs and broad smiles, and the shadows' warmth."""
    shown = ("no change", "global", "elastic", "global+eri", "e+md", "song", "real")
    every, broad = (({s["method"]: s for s in summary}) for summary in summaries.values())
    shown = tuple(name for name in shown if name in every)  # a report of a run without Song et al.'s method
    lines = [
        f"`{meta['command']}` ({meta['date']}, exprclone {meta['version']}):",
        "",
        "| method | mouth error, all pairs | mouth error, broad smiles | identity distance | identity beyond a real smile as wide"
        " | shows teeth when the source does | shadow warmth: median (results with shadows) |",
        "|---|---|---|---|---|---|---|",
    ]
    for name in shown:
        s, b = every[name], broad[name]
        teeth = f"{100 * s['teeth_kept']:.0f}%" if s["teeth_sources"] else "-"
        warmth = f"{s['warmth']:.2f} ({s['warmth_n']})" if s["warmth_n"] else "-"
        excess = "-" if s["excess"] != s["excess"] else f"{s['excess']:+.3f}"
        lines.append(
            f"| {name} | {s['mouth_mean']:.4f} | {b['mouth_mean']:.4f} | {s['identity_mean']:.3f} | {excess} | {teeth} | {warmth} |"
        )
    return "\n".join(lines)


def _printed(folder: Path) -> list[str]:
    """A section for each script's output kept in ``folder``: its command as the title, the run's facts, what it printed."""
    text: list[str] = []
    for output in sorted(folder.glob("*.txt")) if folder.exists() else []:
        meta = json.loads(output.with_suffix(".json").read_text())
        title = f"``{meta['command'].removeprefix('python ')}``"
        text += [title, "-" * len(title), ""] + _facts(meta) + ["::", ""]
        text += ["   " + line if line.strip() else "" for line in output.read_text().splitlines()] + [""]
    return text


def render_speed() -> None:
    """``speed.rst``: each kept benchmark's facts and what it printed."""
    text = ["..", "   Generated by tools/results.py from docs/results/data/bench/: do not edit.", "", "Speed", "=====", ""]
    text += [
        "What the benchmarks in ``benchmarks/`` print, as they printed it: medians, and ratios against a peer measured in the",
        "same run. Wall-clock figures depend on the machine and on what else it runs; the ratios travel better.",
        "",
    ]
    text += _printed(KEPT / "bench") or ["No benchmark has been kept yet: ``python tools/results.py bench NAME``.", ""]
    (PAGES / "speed.rst").write_text("\n".join(text))


def render_video() -> None:
    """``video.rst``: the video judges' facts, their table and their verdicts, as ``tools/video_judges.py`` printed them."""
    output = KEPT / "judges" / "video_judges.txt"
    text = ["..", "   Generated by tools/results.py from docs/results/data/judges/: do not edit.", "", "Driven video", "=" * 12, ""]
    if not output.exists():
        text += ["No run of the judges has been kept yet: ``python tools/results.py judges``.", ""]
        (PAGES / "video.rst").write_text("\n".join(text))
        return
    text += _facts(json.loads(output.with_suffix(".json").read_text()))
    text += [
        "London portraits (the palest and the darkest) driven by every GRID clip (``exprclone video``), each output judged",
        "beside what it should match (in brackets): the teeth's yellowness and lightness over the cheeks (b*, L*) on the",
        "frames where they are in sight, beside the portrait person's own teeth in their real smile; the lip band's fall in",
        "L* when the mouth opens, beside the driver's own; the jitter of the mouth's landmarks where the driver's head is",
        "still, beside the driver's (and the jitter of the output's rendered geometry, beside that of the driver's landmarks as",
        "tracked: the steadiness of the output itself, apart from the detector's on it); the flicker of the mouth interior's",
        "colour, beside the driver's (and beside the driver's interior in the portrait's light: its pixels times the paste's",
        "gain from the driver's light to the portrait's); and the correlation of the mouth's opening with the driver's, from",
        "landmarks found afresh on the output (in brackets: from its rendered geometry). The blendshape judge",
        "(:doc:`../explanation/expression-judge`) reads MediaPipe's 52 expression scores on every frame: the output's",
        "distance to the driving frame's, the mean over the frames (in brackets: the still portrait's, what an output that",
        "never moved would score); the share of the driver's rise the output keeps (on the four scores each driving frame",
        "raises most from the driver's neutral frame, the output's rise from the portrait over the driver's; the median",
        "over the frames); and the correlation of ``jawOpen``, the output's against the driver's.",
        "The judges and their thresholds are in ``tools/video_judges.py``.",
        "",
    ]
    lines = output.read_text().splitlines()
    text += [f"Judged: {lines[0].split(': ', 1)[-1]}.", ""]
    table = [line.split(" | ") for line in lines if line.count(" | ") >= 4]
    if table:
        text += _list_table(table[0], [[cell.strip() for cell in row] for row in table[1:]])
    text += [line if not line.strip() else f"- {line}" for line in lines[lines.index("") + 1 :] if " | " not in line and "---" not in line]
    (PAGES / "video.rst").write_text("\n".join(text) + "\n")


def update_readme(headline: str) -> None:
    """The README's headline table, between its results markers."""
    readme = ROOT / "README.md"
    text = readme.read_text()
    start, end = "<!-- results:start -->\n", "<!-- results:end -->"
    before, rest = text.split(start)
    readme.write_text(before + start + headline + "\n" + end + rest.split(end, 1)[1])


def render() -> None:
    headline = render_evaluation()
    render_speed()
    render_video()
    render_elastic()
    if headline:
        update_readme(headline)


def main(argv: list[str]) -> None:
    """``evaluate ARGS``, ``bench NAME ARGS``, ``judges ARGS``, ``split ARGS``, ``db ARGS`` or ``render`` (the module's
    notes); what follows is the command's own."""
    what = argv[0] if argv else ""
    if what == "evaluate":
        collect_evaluate(argv[1:])
    elif what == "bench" and len(argv) > 1:
        collect_bench(argv[1], argv[2:])
    elif what == "judges":
        _collect_printed(ROOT / "tools" / "video_judges.py", argv[1:], KEPT / "judges")
    elif what == "split":
        _collect_printed(ROOT / "tools" / "identity_split.py", argv[1:], KEPT / "split")
    elif what == "db":
        _collect_printed(ROOT / "tools" / "db_terms.py", argv[1:], KEPT / "db", "-evaluated" if "--evaluated" in argv else "")
    elif what in ("-h", "--help"):
        print(__doc__)
        return
    elif what != "render":
        sys.exit(__doc__)
    render()


if __name__ == "__main__":
    main(sys.argv[1:])
