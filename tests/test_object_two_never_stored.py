"""A candidate known to be two objects (``two``: the camera saw two things there, one behind the other, that it
could not tell apart in depth) is never stored at the point between them (issue 26 item 5, review17 F2): with no
place to see them apart from, or still two from there, the robot asks which one she means, front or back, and
stores the one she picks; unanswered, it has not found it."""
import asyncio
from types import SimpleNamespace

import pytest

from robot.objects.attention import ObjectAttention
from tests.object_attention_probe import bare_search_state
from robot.objects.resolve import Resolution

FRONT = SimpleNamespace(two=False, x=1.9, y=0.0, z=0.8, parts=())
BACK = SimpleNamespace(two=False, x=2.1, y=0.0, z=0.8, parts=())


class _Probe(ObjectAttention):
    def __init__(self, place: bool, two_again: bool, answer: int | None):
        bare_search_state(self)
        self.place, self.two_again, self.answer = place, two_again, answer
        self.stored, self.asked, self.looks = [], [], 0

    def _listen(self, on): pass
    def _out_of_range(self, pointing): return False
    def _partner_in_the_way(self, pointing): return False

    async def _look(self, wanted, pointing, cause):
        self.looks += 1
        two = self.looks == 1 or self.two_again
        cand = SimpleNamespace(two=two, x=2.0, y=0.0, z=0.8, parts=(FRONT, BACK) if two else ())
        return Resolution("one", (SimpleNamespace(candidate=cand, fits=True),))

    async def _move_to_see_spot(self, target, cause, apart_from=None):
        return self.place

    async def _ask(self, cands, wanted, pose, cause, first=None):
        self.asked.append(list(cands))
        return None if self.answer is None else cands[self.answer]

    def _not_found(self, reason, cause): self.stored.append("not found")
    def _recognized(self, c, wanted, obj, cause): self.stored.append(c)


@pytest.mark.parametrize("place,two_again", [(False, False), (True, True)])
@pytest.mark.parametrize("answer", [None, 0, 1])
def test_two_things_there_are_asked_about_never_stored_between(place, two_again, answer):
    p = _Probe(place, two_again, answer)
    asyncio.run(p.find(None, "cause"))
    assert all(getattr(s, "two", False) is False for s in p.stored), "stored the point between two objects"
    assert p.asked == [[FRONT, BACK]], "did not ask front or back"
    assert p.stored == (["not found"] if answer is None else [(FRONT, BACK)[answer]])


def test_two_seen_apart_from_another_side_is_stored_without_asking():
    p = _Probe(place=True, two_again=False, answer=None)
    asyncio.run(p.find(None, "cause"))
    assert p.asked == [] and len(p.stored) == 1 and p.stored[0].two is False
