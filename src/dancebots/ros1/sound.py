"""Speech and beeps for sound_play (thesis 5.2), whose message package Debian does not ship.

The sound_play/SoundRequest class is generated at run time by genpy from the message's
definition (the fields of ROS 1 sound_play's SoundRequest.msg; ``genpy_types.
message_classes``, which leaves no temporary files), so a sound_play node on a robot
receives it like its own: ``say_request`` speaks a sentence, ``beep_request`` plays
the built-in BACKINGUP beep.
"""

from __future__ import annotations

from typing import Any

from dancebots.genpy_types import message_classes

__all__ = ["SoundRequest", "beep_request", "say_request"]

_DEFINITION = """\
int8 BACKINGUP=1
int8 NEEDS_UNPLUGGING=2
int8 NEEDS_PLUGGING=3
int8 NEEDS_UNPLUGGING_BADLY=4
int8 NEEDS_PLUGGING_BADLY=5
int8 ALL=-1
int8 PLAY_FILE=-2
int8 SAY=-3
int8 sound
int8 PLAY_STOP=0
int8 PLAY_ONCE=1
int8 PLAY_START=2
int8 command
float32 volume
float32 reverb
string arg
string arg2
"""

SoundRequest: Any = message_classes({"sound_play/SoundRequest": _DEFINITION})[
    "sound_play/SoundRequest"]


def say_request(text: str, volume: float = 1.0) -> Any:
    """Say ``text`` once."""
    return SoundRequest(sound=SoundRequest.SAY, command=SoundRequest.PLAY_ONCE,
                        volume=volume, arg=text, arg2="")


def beep_request(volume: float = 1.0) -> Any:
    """Play the built-in beep once."""
    return SoundRequest(sound=SoundRequest.BACKINGUP, command=SoundRequest.PLAY_ONCE,
                        volume=volume, arg="", arg2="")
