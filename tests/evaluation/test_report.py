"""evaluate's report (:mod:`exprclone.evaluation.report`): the methods that score exactly alike, and why."""

from exprclone.evaluation.report import TOLD_BY, alike


def test_methods_score_alike_within_their_variant_and_say_why():
    """Rows of two variants of one method are never compared across them, and the reason follows the variant: with
    retarget (no mark) LI is GI; by the paper's stages the elastic model at lambda_k 0 is its GI, and local re-shaping
    that differs is not named."""

    def row(method, variant, score, lam=""):
        return {
            "source": "a",
            "target": "b",
            "method": method,
            "variant": variant,
            "failed": "",
            "lambda_k": lam,
            **dict.fromkeys(TOLD_BY, score),
        }

    paper = " [no retarget]"
    rows = [row("global", "", 0.2), row("local", "", 0.2), row("elastic", "", 0.2, 0.0)]
    rows += [row("global", paper, 0.1), row("local", paper, 0.3), row("elastic", paper, 0.1, 0.0)]
    said = alike(rows)
    assert len(said) == 3, said
    assert said[0].startswith("local scores exactly as global") and "LI is GI" in said[0]
    assert said[1].startswith("elastic scores exactly as global") and "LI is GI" in said[1]
    assert said[2].startswith("elastic [no retarget] scores exactly as global [no retarget]") and "DB metric chose" in said[2]
