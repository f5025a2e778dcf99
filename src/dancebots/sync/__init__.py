"""Start synchronisation (thesis ch. 3 and 4.2) as pure state machines.

``network_test``: every robot checks that it hears every other robot and is heard back (the
echo test of the ``network_test`` node) before it says it is ready. ``start``: the robots
agree on one start time for the virtual leader from proposals each makes when it is ready, ignoring
implausible ones (a window around the receiver's clock).
Messages are plain text as they travel on the shared ``/sync`` topic (std_msgs/String); the
formation's shared show clock (``hold``) sends its own on ``/hold``.
"""

from dancebots.sync.messages import (
    EchoMessage,
    HoldMessageError,
    ShowMessage,
    StartProposal,
    SyncMessageError,
    format_hold,
    format_message,
    is_role,
    parse_hold,
    parse_message,
)
from dancebots.sync.network_test import NetworkTest, network_test_receive, start_network_test
from dancebots.sync.start import (
    MAX_CLOCK_OFFSET,
    PLAUSIBLE_AHEAD,
    PLAUSIBLE_BEHIND,
    START_DELAY,
    START_STRATEGIES,
    TIMECODE_OFFSET,
    StartAgreement,
    agreement_ready,
    agreement_receive,
    agreement_show,
    implausible,
    new_agreement,
    show_time,
)

__all__ = [
    "MAX_CLOCK_OFFSET",
    "PLAUSIBLE_AHEAD",
    "PLAUSIBLE_BEHIND",
    "START_DELAY",
    "START_STRATEGIES",
    "TIMECODE_OFFSET",
    "EchoMessage",
    "HoldMessageError",
    "NetworkTest",
    "ShowMessage",
    "StartAgreement",
    "StartProposal",
    "SyncMessageError",
    "agreement_ready",
    "agreement_receive",
    "agreement_show",
    "format_hold",
    "format_message",
    "implausible",
    "is_role",
    "network_test_receive",
    "new_agreement",
    "parse_hold",
    "parse_message",
    "show_time",
    "start_network_test",
]
