"""The FE studies' sequence wording (``bench/fe_ring3d_combinations.order_text``, the sentence of
``bench/fe_ring3d.combinations_sentence``) called a sequence whose ``symmetric`` is null "asymmetric": null is an
order that could not be completed, or nothing that snapped (``analysis.sequence_symmetry``), neither symmetric nor
asymmetric. Now they say what ``analysis.symmetry_word`` says (``undetermined`` / ``nothing snapped``); a record
stored without its events (the frame's ``model`` entries) is ``undetermined``."""
import pytest

from metamaterial_wb.bench import fe_ring3d
from metamaterial_wb.bench import fe_ring3d_combinations as fc

EVENT = {"d": 0.2, "units": [0], "snapped": True}


@pytest.mark.parametrize("seq, word", [
    ({"loading": [0, 1], "unloading": [1, 0], "symmetric": True}, "symmetric"),
    ({"loading": [0, 1], "unloading": [0, 1], "symmetric": False}, "asymmetric"),
    ({"loading": [0], "unloading": [0, 1], "symmetric": None, "events_loading": [EVENT], "events_unloading": []},
     "undetermined"),                            # a type not ordered on the loading path
    ({"loading": [], "unloading": [], "symmetric": None, "events_loading": [], "events_unloading": []},
     "nothing snapped"),
    ({"loading": [0, 1], "unloading": [0], "symmetric": None}, "undetermined"),      # stored without its events
    ({"loading": [], "unloading": [], "symmetric": None}, "undetermined"),
], ids=["symmetric", "asymmetric", "incomplete", "nothing-snapped", "stored", "stored-empty"])
def test_order_text_says_what_the_sequence_is(seq, word):
    assert fc.order_text(seq) == f"{seq['loading']} \\| {seq['unloading']} ({word})"


def test_the_report_sentence_does_not_call_null_asymmetric(monkeypatch):
    """``combinations_sentence`` (fe_ring3d.md) words the rule's order the same way."""
    monkeypatch.setattr(fc, "extrapolated", lambda c: {"differences": {"P1": (1.0, 0.1), "valley": (2.0, 0.2)}})
    for symmetric, word in ((None, "undetermined"), (False, "asymmetric"), (True, "symmetric")):
        monkeypatch.setattr(fc, "extrapolated_rule", lambda ex: {"loading": [0, 1], "unloading": [0],
                                                                 "symmetric": symmetric})
        text = fe_ring3d.combinations_sentence({"combinations": {"2": {}}})
        assert f"snap loading [0, 1], unloading [0] ({word}), the seed's order" in text, text
