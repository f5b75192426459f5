"""Illumination details (the paper's Sec. III-B): the expression ratio image and the muscle-distribution model.

- :mod:`.eri`: Liu et al.'s expression ratio image, its filters and its application.
- :mod:`.coarse`: the ERI's photos shrunk once over the face and warped at that size (ours, for speed).
- :mod:`.gate`: where the ERI counts: only skin that the expression moves and all three photos show (ours).
- :mod:`.stage`: the ERI of one clone: the neutral photos measured once, the ratio in FI's geometry.
- :mod:`.mesh_image`: Song et al.'s mesh image: the ratio made on one mesh shared by both faces, brought onto FI.
- :mod:`.muscle`: the MD model, Eqs. (9)-(11): where the details matter.
"""
