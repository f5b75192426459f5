"""The source's light is not its expression (issue 57): a change of light in the source's expression photo alone,
relit from one side or given another white balance, leaves the clone as it was."""

import pytest

import exprclone
from exprclone.testing.lighting import change, changes, face

#: issue 57's bound: the clone changes by at most 0.7 grey levels on average inside the face (R, G and B). Measured with
#: the source's landmarks kept, so that the light's share is what is measured: found afresh on a changed photo, dlib's
#: points move by about 2 pixels and the clone by about 1.7 grey levels, as they do for noise of one grey level
#: (``tools/relight.py``). Carried as expression (the ratio's trend not divided out), the relit light changed this clone
#: by 6.8 grey levels.
MOST = 0.7
#: the change of light itself, in the source's face, is many times that (grey levels on average: 9 to 10 here).
CHANGED = 4.0


@pytest.fixture(scope="module")
def made(pair):
    """E+MD's clone of the pair, as the product makes it."""
    images, landmarks = pair
    return exprclone.clone(*images, landmarks=landmarks)


@pytest.mark.parametrize("light", ["relit+", "relit-", "warm", "cool"])
def test_a_change_of_light_in_the_source_does_not_reach_the_clone(pair, made, light):
    (neutral, smile, target), landmarks = pair
    lit = changes(smile, landmarks[1])[light]
    assert change(smile, lit, face(smile.shape, landmarks[1]))[0] > CHANGED
    again = exprclone.clone(neutral, lit, target, landmarks=landmarks)
    assert change(made.image, again.image, face(target.shape, made.landmarks["final"]))[0] <= MOST
