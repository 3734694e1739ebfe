"""``deck-emulator scene``: write a deck's scene as TOML (to edit by hand, then `core`)"""

from __future__ import annotations

from . import Answer, command
from . import common
from .groups import SceneSource
from .options import option, options_class


@options_class
class SceneOptions(SceneSource):
    out: str | None = option(None, metavar="FILE", help="write to FILE instead of stdout")
    json: bool = option(False, help="print the scene (the TOML's tables) as one JSON object "
                        "(docs/json.md)")


@command("scene", SceneOptions,
         help="write a deck's scene as TOML (to edit by hand, then `core`)")
def scene(o: SceneOptions) -> Answer:
    import tomllib

    src = common.load(o, "scene")
    made = common.engine_scene(src.scene_or_deck("scene"), name=src.stem)
    common.check_out(o.out)
    text = made.to_toml()
    return Answer("scene", src.name, notes=list(src.notes), said=list(src.notes),
                  result={"scene": tomllib.loads(text)} if o.json else {}, text=text,
                  json=o.json, out=o.out)
