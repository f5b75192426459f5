"""Geometric warping (the paper's Sec. III-A, Fig. 5's GI, LI and FI's landmarks): where the target's landmarks go.

- :mod:`.global_warp`: GI, the source's motion carried to the target (Liu et al.), or by an RBF map (Seol and Lewis).
- :mod:`.vtc`: GI by vertex-tent-coordinate transfer (Song et al.), each tent of the landmark mesh changed as the source's.
- :mod:`.local_warp`: LI, each organ re-shaped to the source's, Eqs. (1)-(2).
- :mod:`.elastic`: the elastic model's balance of the two, Eqs. (3)-(6).
- :mod:`.db_metric`: the distance-based metric that picks lambda_k, Eqs. (7)-(8), on the features of :mod:`.eigenface`.
- :mod:`.retarget`: the source's motion made the target's (ours, not in the paper).
- :mod:`.weights`: how much of the motion and details is transferred, and where (strength and regions; ours).
"""
