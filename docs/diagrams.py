"""The architecture page's picture, drawn when the documentation is built (``docs/conf.py``): the data's way through
the package's rooms, the paper's Fig. 5 as modules, with the surfaces around it."""

from __future__ import annotations

from pathlib import Path

#: the way of one clone, top to bottom: (room, what it does there, its modules).
STEPS = (
    (
        "surfaces",
        "command line, Python, HTTP, live, batch, video, evaluate: each describes its inputs and options",
        "cli server batch drive evaluation clone",
    ),
    ("io", "the inputs gathered: files or bytes sent read into one Request (gather)", "inputs images landmarks"),
    ("options", "every option declared once: Options, Driving, Framing", "options"),
    (
        "pipeline",
        "the door: the request checked, its landmarks placed, its roles checked once per photo, the Cloner made",
        "request checks role_check group",
    ),
    ("landmarks", "the 68 points of each photo, placed once (dlib or the face mesh) or given", "backends dlib facemesh layout align lips"),
    ("pipeline", "prepare: the two neutral faces (Faces) and the source expression, once", "cloner faces stages"),
    (
        "geometry",
        "GI (global warp), LI (Eqs. 1-2), the elastic model (Eqs. 3-6), lambda_k by the DB metric (Eqs. 7-8)",
        "global_warp local_warp elastic db_metric eigenface retarget",
    ),
    ("pipeline", "render: stages over the prepared data (strength and regions), as often as asked", "render result"),
    ("imaging", "FI: the target photo warped to the final landmarks (mesh or TPS)", "piecewise tps warpers raster"),
    ("details", "the ERI in FI's geometry, gated; the MD mask (Eqs. 9-11)", "stage eri coarse gate muscle"),
    ("mouth", "the source's mouth interior pasted into an opened mouth", "paste tone teeth illuminant camera measure"),
    ("result", "F_IMG, with every intermediate (CloneResult)", ""),
)
COLOURS = {
    "surfaces": "#e8e8e8",
    "io": "#e0efe9",
    "options": "#f3e6c4",
    "landmarks": "#d6e6f5",
    "pipeline": "#e3d7ef",
    "geometry": "#d5ecd4",
    "imaging": "#f5ddd0",
    "details": "#f7d6e0",
    "mouth": "#f9edc9",
    "result": "#ffffff",
}


def draw(target: Path) -> None:
    """Write the picture to ``target`` (PNG) unless it is there already and newer than this file."""
    if target.exists() and target.stat().st_mtime >= Path(__file__).stat().st_mtime:
        return
    import matplotlib

    matplotlib.use("agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import FancyBboxPatch

    height = 0.9
    figure, axes = plt.subplots(figsize=(10, 0.62 * len(STEPS) + 0.3), dpi=110)
    axes.set_xlim(0, 10)
    axes.set_ylim(-0.3, len(STEPS) * 1.0)
    axes.axis("off")
    for k, (room, what, modules) in enumerate(STEPS):
        y = len(STEPS) - 1 - k
        box = FancyBboxPatch((0.1, y + 0.05), 9.8, height - 0.1, boxstyle="round,pad=0.02", fc=COLOURS[room], ec="#555555", lw=0.8)
        axes.add_patch(box)
        axes.text(0.3, y + height / 2, room, va="center", ha="left", fontsize=10, weight="bold", family="monospace")
        axes.text(2.0, y + height / 2 + 0.14, what, va="center", ha="left", fontsize=8.5)
        axes.text(
            2.0,
            y + height / 2 - 0.2,
            "   ".join(modules.split()),
            va="center",
            ha="left",
            fontsize=7.5,
            family="monospace",
            color="#444444",
        )
        if k:
            axes.annotate("", (1.2, y + height - 0.04), (1.2, y + 1.06), arrowprops={"arrowstyle": "-|>", "color": "#555555", "lw": 1})
    figure.tight_layout()
    target.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(target)
    plt.close(figure)
