"""The mouth interior: teeth, tongue and cavity where the target's closed mouth opens (ours, not in the paper).

- :mod:`.measure`: how wide and how open a mouth is, and what it shows between the lips.
- :mod:`.paste`: the source's interior pasted into the target's opened mouth.
- :mod:`.tone`: the paste matched to the target photo's light, sharpness and noise.
- :mod:`.illuminant`: the light on a face, read from its skin and eye whites.
- :mod:`.camera`: how blurred and how noisy a photo is.
- :mod:`.teeth`: teeth and cavity in white light, a prior for the paste.
"""
