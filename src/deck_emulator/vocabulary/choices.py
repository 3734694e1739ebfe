"""The names of the program's choices, one row each: the emulator's arithmetics, the listing's
errata, the core's presets, the engines, the pictures' views, the card images' formats and the
keypunch codes.

The layers that implement a choice key their tables by these names, and the command line
offers them from here, without importing those layers at its start.
"""

#: the emulator's arithmetics, in the order the command line offers them
ARITHMETICS = ("double", "single", "ibm7094")

#: the listing's errata (legacy/errata/NAME.patch: patches to the listing's statements) by
#: name, with what each changes
ERRATA = {
    "ed-direction": "ED steps towards its root in the branch 'ROOT GOES NEGATIVE TO POSITIVE' "
    "(labels 1 and 15: DH=D-H, DH=D-H/2.)",
}

#: the core's model presets (vocabulary/scene.py PRESETS: the model options of each)
PRESETS = ("legacy", "physical")

#: the engines: the 1967 program and the modern core
ENGINES = ("emulator", "core")

#: the trajectory picture's views
VIEWS = ("side", "plan", "3d", "all")

#: the card images' formats (legacy/cardimage.py reads and writes each)
CARD_FORMATS = ("text", "binary", "cbn", "bcd")

#: the keypunch codes (legacy/keypunch.py: the 026's and the 029's punch combinations)
KEYPUNCH_CODES = ("026", "029")
