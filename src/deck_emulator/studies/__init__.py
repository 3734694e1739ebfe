"""What is computed from runs, each run asked of an engine."""

#: Where a command that runs many scenes (sweep, sensitivity's decks aside, the studies) keeps
#: them as they finish, inside its output folder, for --resume. Here, so that the command
#: line names it without importing the runner.
SCENE_STORE = ".scenes"
