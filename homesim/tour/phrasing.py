"""How a generated user words each request of the home tour (the generator's own bank).

Several everyday phrasings per request, chosen at random from the tour's
seed. This bank is the generated user's, written for the generator; it is not
the robot's understanding corpus (robot/speech), so a generated tour also
measures how well the robot understands words it was not tuned on.

Each entry is a template: ``{word}`` is the user's word for an object or a
room, ``{colour}`` its colour. Object words per type (``OBJECT_WORDS``) are
household words a person uses for that type, all of them words of the robot's
lexicon for the type (tests/test_tour_generate.py checks it).
"""

from __future__ import annotations

GREET = ("Hello BIRON", "Hi BIRON", "Hello robot", "Good morning BIRON", "Hey BIRON", "Hello",
         "Hi there BIRON", "Good evening BIRON")
GREET_AGAIN = ("Hello again BIRON", "Hi BIRON, I am back", "Hello BIRON", "Hey BIRON")
CAPABILITIES = ("What can you do", "What can you do for me", "Tell me what you can do",
                "What are you able to do", "So what can you do")
FOLLOW = ("Follow me", "Please follow me", "Come with me", "Follow me please", "Can you follow me",
          "Could you follow me please", "Come along with me")
STOP = ("Stop", "Stop here", "Please stop", "OK stop", "You can stop now", "Stop please")
PLACE = ("This is the {word}", "Here is the {word}", "This room is the {word}", "And this is the {word}",
         "This is my {word}", "We are in the {word}")
#: (template, owner said, "favourite" said, colour said)
OBJECT = (("This is my {word}", True, False, False),
          ("This is my favourite {word}", True, True, False),
          ("This is the {word}", False, False, False),
          ("This is a {word}", False, False, False),
          ("Here is my {word}", True, False, False),
          ("Look, this is the {word}", False, False, False),
          ("That is my {word}", True, False, False),
          ("This is the {colour} {word}", False, False, True),
          ("This is my {colour} {word}", True, False, True))
#: With a similar object next to it, the user says the colour.
OBJECT_SIMILAR = (("This is the {colour} {word}", False, False, True),
                  ("This is my {colour} {word}", True, False, True),
                  ("Look, this {colour} {word} is mine", True, False, True))
WHERE = ("Where is my {word}", "Where is the {word}", "Do you know where my {word} is",
         "Where did I put my {word}", "Can you tell me where the {word} is")
GOTO = ("Go to the {word}", "Please go to the {word}", "Can you go to the {word}", "Drive to the {word}",
        "Go to the {word} please")
GOODBYE = ("Good bye", "Goodbye BIRON", "Bye BIRON", "Bye bye", "Thank you, good bye", "Good bye robot")

#: The user's words for each object type (first: the usual one).
OBJECT_WORDS: dict[str, tuple[str, ...]] = {
    "cup": ("cup", "mug"),
    "glass": ("glass",),
    "bottle": ("bottle",),
    "plant": ("plant", "flower"),
    "remote_control": ("remote control", "remote"),
    "book": ("book", "magazine"),
    "lamp": ("lamp",),
    "phone": ("phone", "telephone"),
    "keys": ("keys",),
    "bag": ("bag",),
    "clock": ("clock",),
    "vase": ("vase",),
    "plate": ("plate",),
    "bowl": ("bowl",),
    "teapot": ("teapot",),
    "kettle": ("kettle",),
    "computer": ("laptop", "computer"),
    "glasses": ("glasses",),
    "ball": ("ball",),
    "toy": ("teddy bear", "toy", "teddy"),
    "umbrella": ("umbrella",),
    "shoes": ("shoes",),
}

#: Object words a person uses in the plural ("where are my keys").
PLURAL = frozenset({"keys", "glasses", "shoes", "flowers"})

_AGREE = ((r"\bThis is\b", "These are"), (r"\bThat is\b", "Those are"), (r"\bHere is\b", "Here are"),
          (r"\bWhere is\b", "Where are"), (r"\bthis is\b", "these are"), (r"\bthis\b", "these"), (r"\bis mine\b", "are mine"),
          (r"\b(where (?:my|the) [a-z ]+) is\b", r"\1 are"), (r"\bThese are a\b", "These are"))


def agree(text: str, word: str) -> str:
    """``text`` about ``word`` with the verb and pronoun in agreement ("This is a keys" -> "These are keys")."""
    import re

    if word not in PLURAL:
        return text
    for pattern, repl in _AGREE:
        text = re.sub(pattern, repl, text)
    return text


#: What bystanders say to each other (never addressed to the robot).
CHAT = ("Did you see the game last night", "We need to buy milk", "The weather is nice today",
        "When is dinner", "I will call my sister later", "Have you seen my keys", "This new robot is funny",
        "Shall we go for a walk later", "The garden needs water", "I am so tired today",
        "What time is it", "Let us watch a film tonight")
#: What a radio or a TV says (sometimes a greeting nobody meant for the robot).
BROADCAST = ("This is the news at ten", "And now the weather forecast", "Traffic is heavy on the motorway",
             "Stay tuned for more music", "The match ended two to one", "Good evening and welcome to the show")
BROADCAST_GREETING = ("Hello BIRON, this is the news at ten", "Hello and welcome to the morning show",
                      "Hi everybody, good morning")
