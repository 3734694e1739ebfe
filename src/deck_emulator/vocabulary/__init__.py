"""The shared vocabulary every layer reads and none owns: units and their conversions
(:mod:`.units`), the typed events (:mod:`.events`), every default (:mod:`.defaults`).
Nothing here imports numpy or anything heavier."""
