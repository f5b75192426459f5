"""Driving a portrait from a performance (the paper's Sec. IV, Fig. 18): :mod:`.tracking` follows the face through the
frames, :mod:`.driver` clones each frame's expression onto the portrait.

>>> from exprclone import drive
>>> drive.prepare is drive.driver.prepare
True
"""

from .driver import DrivenFrame, Driver, Recording, prepare

__all__ = ["DrivenFrame", "Driver", "Recording", "prepare"]
