"""What raildyn.assess reads from a stored deck: groups, strings with the namelist's special
characters, overrides, shared frames."""
from raildyn.assess.layout import _frame_offset, _merged, deck_groups

DECK = """&simulation title = 'a, b = c / d ! e', t_end = 2.0 /   ! a comment with = and /
&body name = 'car', mass = 1.0, frame_offset = 1.5d0 /
&body name = "bogie", frame = 'car',
      mass = 2.0 /
&body name = 'ws1', frame_offset = 3.0 / &body name = 'ws2', frame = 'bogie' /
&wheelset name = 'w1', body = 'ws1', wheel_profile = 'dir/x.prf' /
&body name = 'ws1', frame_offset = 4.25 /
"""


def test_groups_strings_and_comments():
    groups = deck_groups(DECK)
    assert [g for g, _ in groups] == ["simulation", "body", "body", "body", "body", "wheelset", "body"]
    assert groups[0][1] == {"title": "a, b = c / d ! e", "t_end": "2.0"}
    assert groups[5][1] == {"name": "w1", "body": "ws1", "wheel_profile": "dir/x.prf"}
    assert groups[2][1]["frame"] == "car" and groups[2][1]["mass"] == "2.0"


def test_offsets_overrides_and_shared_frames():
    bodies = _merged(deck_groups(DECK), "body")
    assert _frame_offset(bodies, "ws1") == 4.25          # the later group overrides
    assert _frame_offset(bodies, "car") == 1.5            # Fortran d exponent
    assert _frame_offset(bodies, "ws2") == 1.5            # ws2 -> bogie -> car's frame
