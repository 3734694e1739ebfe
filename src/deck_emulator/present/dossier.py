"""A run's dossier as one self-contained HTML page: ``run --html``, ``compare --html``,
``diff --html`` (what the page shows and why: docs/dossier.md).

Everything said about the run is read from what the commands already computed (the
provenance's facts, the summary's answer, the comparison's and the diff's results); nothing is
computed again here. Nothing from a card, a file or the command line reaches the page but as
text escaped for it (:func:`html.escape`); the one JSON block is escaped so that it cannot end
its script element.
"""

from __future__ import annotations

import html
import importlib.util
import io
import json
from dataclasses import dataclass, field

from deck_emulator.vocabulary import defaults

__all__ = ["CSP", "ListedCard", "WriteStatement", "PrintedSection", "Program", "run_page",
           "compare_page", "diff_page", "pictures"]

#: The page's policy: nothing may be fetched (a request a browser would make is blocked and
#: reported), only the page's own style, script and data: images.
CSP = ("default-src 'none'; style-src 'unsafe-inline'; script-src 'unsafe-inline'; "
       "img-src data:")

#: Print positions of the line printer (after the carriage control in column 1).
POSITIONS = defaults.PRINT_POSITIONS


def _e(text) -> str:
    return html.escape(str(text), quote=True)


# ------------------------------------------------------------------------------ the data


@dataclass(frozen=True)
class ListedCard:
    """A card of the program's listing: its ``number`` (the card's place in the source the
    run's statements name: the line of luminaire.f as run, or the job deck's card), its
    ``text``, the internal statement number (``isn``) on a statement's first card, and the
    program unit it belongs to."""

    number: int
    text: str
    isn: int | None = None
    unit: str | None = None


@dataclass(frozen=True)
class WriteStatement:
    """A WRITE statement of the program: its card, unit, text, FORMAT label, the card of that
    FORMAT and the names of its list (as punched)."""

    card: int
    unit: str
    text: str
    fmt: int
    format_card: int | None
    names: tuple[str, ...] = ()
    format_text: str = ""  # the FORMAT statement as punched, its continuation cards joined


@dataclass(frozen=True)
class Program:
    """The program that printed: what it is (a line for the heading), its cards, and its
    WRITE statements by card."""

    title: str
    cards: tuple[ListedCard, ...]
    writes: dict = field(default_factory=dict)  # (unit, card) -> WriteStatement


@dataclass(frozen=True)
class PrintedSection:
    """One $DATA section's printout: its deck, the settings it ran with, its records and
    which WRITE printed which of them (the run's ``writes``: (first record, unit, card,
    FORMAT, values))."""

    deck: str
    settings: str
    records: tuple[str, ...]
    writes: tuple = ()


# ------------------------------------------------------------------------------ the page

_STYLE = """
:root{--ink:#1b1b1b;--muted:#555;--bar:#dcebd8;--paper:#fffef8;--hi:#ffe58a;--bad:#b00020;
--warn:#8a5a00;--ok:#1d6b2a;--line:1.25em;font-family:system-ui,-apple-system,"Segoe UI",
Roboto,sans-serif;color:var(--ink);background:#f3f3f0}
body{margin:0;line-height:1.4}
a{color:#0b4f9c}
:focus-visible{outline:3px solid #0b4f9c;outline-offset:1px}
.skip{position:absolute;left:-999px}.skip:focus{left:1rem;top:1rem;background:#fff;padding:.5rem;z-index:9}
header.top,main>section{padding:.5rem 1.25rem}
header.top{background:#fff;border-bottom:1px solid #ccc}
h1{font-size:1.4rem;margin:.3rem 0}h2{font-size:1.15rem;margin:1rem 0 .4rem}
h3{font-size:1rem;margin:.6rem 0 .3rem}
nav ul{display:flex;flex-wrap:wrap;gap:.2rem 1.2rem;list-style:none;padding:0;margin:.3rem 0}
.stop{border:3px solid var(--bad);background:#fff0f0;padding:.6rem 1rem;margin:.5rem 0}
.stop strong{color:var(--bad)}
dl.facts{display:grid;grid-template-columns:max-content 1fr;gap:.15rem 1rem;margin:.3rem 0}
dl.facts dt{font-weight:600}dl.facts dd{margin:0;overflow-wrap:anywhere}
table{border-collapse:collapse;background:#fff;margin:.3rem 0}
th,td{border:1px solid #ccc;padding:.15rem .5rem;text-align:left;vertical-align:top}
td.num{text-align:right;font-variant-numeric:tabular-nums;font-family:ui-monospace,monospace}
.note{color:var(--muted)}
.verdict-ok{color:var(--ok);font-weight:600}.verdict-bad{color:var(--bad);font-weight:600}
.pictures figure{background:#fff;margin:.5rem 0;padding:.5rem;border:1px solid #ccc;max-width:100%}
.pictures svg{max-width:100%;height:auto}
.beside{display:grid;grid-template-columns:minmax(0,1fr) minmax(0,40rem);gap:1rem;align-items:start}
@media (max-width:100rem){.beside{grid-template-columns:minmax(0,1fr)}}
.paper{overflow-x:auto;padding-bottom:.5rem}
pre.form,pre.listing,.ruler{font-family:ui-monospace,"DejaVu Sans Mono",Menlo,Consolas,monospace;
font-size:12px;line-height:var(--line);margin:0}
pre.form{background-color:var(--paper);background-image:repeating-linear-gradient(to bottom,
transparent 0,transparent calc(3*var(--line)),var(--bar) calc(3*var(--line)),var(--bar) calc(6*var(--line)));
width:calc(@FORM@ch + 3rem);padding:var(--line) 1.5rem;border-left:1rem dotted #c9c9c0;
border-right:1rem dotted #c9c9c0;margin:0 0 1rem;box-shadow:0 1px 3px #0003}
.ruler{width:calc(@FORM@ch + 3rem);padding:0 2.5rem;color:var(--muted);white-space:pre}
.r{display:inline-block;width:@LINE@ch;vertical-align:top;white-space:pre}
.r.o{margin-left:-@LINE@ch}
.r i{font-style:normal;color:#9a9a90;display:inline-block;width:1ch}
a.w{color:inherit;text-decoration:none}
a.w:hover .r,a.w:focus .r,a.w.on .r{background:var(--hi)}
.listcol{position:sticky;top:0;max-height:100vh;display:flex;flex-direction:column}
.listcol .box{background:#fff;border:1px solid #ccc;padding:.4rem .6rem;margin-bottom:.4rem;font-size:.9rem}
.listcol .scroll{overflow:auto;background:#fff;border:1px solid #ccc;flex:1;min-height:20rem}
pre.listing{padding:.3rem 0}
pre.listing .c{display:inline-block;min-width:100%}
pre.listing .c:target,pre.listing .c.on{background:var(--hi)}
pre.listing .c.f{background:#e3ecff}
pre.listing .c.hit{background:#c8f0c8}
pre.listing b{font-weight:normal;color:var(--muted)}
.search{display:flex;gap:.4rem;align-items:center;flex-wrap:wrap}
table.aligned{font-family:ui-monospace,monospace;font-size:12px}
table.aligned td{white-space:pre;border-color:#e3e3e3}
tr.differ td{background:#ffe1e1}tr.damaged td{background:#fff3cf}
tr.unreadable td{background:#ffd0a8}tr.missing td{background:#e9e0ff}
.counts td{font-variant-numeric:tabular-nums}
@media print{
 .skip,nav,.search,.listcol .box,.noprint{display:none!important}
 body{background:#fff}
 .beside{display:block}.listcol{position:static;max-height:none}.listcol .scroll{overflow:visible;border:0}
 pre.form{page-break-before:always;box-shadow:none;border:0;width:auto;font-size:8px}
 .ruler{display:none}
 a.w .r{background:none!important}
 .pictures figure{page-break-inside:avoid}
}
"""

# a record's line: the control column and the print positions; a form: a little margin more
_STYLE = _STYLE.replace("@LINE@", str(POSITIONS + 1)).replace("@FORM@", str(POSITIONS + 2))

# The script adds the detail box of the focused record (its WRITE, FORMAT and values, read
# from the link's title and the listing), the listing's scroll to the WRITE and the search;
# the page reads the same without it.
_SCRIPT = r"""
(function(){
var info=JSON.parse(document.getElementById('writes').textContent);
var box=document.getElementById('detail');var last=[];
function clear(){last.forEach(function(e){e.classList.remove('on','f')});last=[];}
function mark(id,cls){var e=document.getElementById(id);if(e){e.classList.add(cls);last.push(e);}return e;}
function show(a){
 clear();a.classList.add('on');last.push(a);
 var card=a.getAttribute('href').slice(1),w=info[card.slice(1)]||{};
 var e=mark(card,'on');if(w.f){mark('c'+w.f,'f');}
 if(e&&box){var s=e.closest('.scroll');if(s){s.scrollTop=e.offsetTop-s.clientHeight/3;}}
 if(!box)return;box.textContent='';
 function line(label,text,href){var p=document.createElement('p');p.style.margin='.1rem 0';
  var b=document.createElement('strong');b.textContent=label+' ';p.appendChild(b);
  if(href){var l=document.createElement('a');l.href=href;l.textContent=text;p.appendChild(l);}
  else{p.appendChild(document.createTextNode(text));}box.appendChild(p);}
 line('WRITE',(w.t||'')+' (card '+card.slice(1)+', '+(w.u||'')+')','#'+card);
 if(w.f){var fc=document.getElementById('c'+w.f);line('FORMAT '+w.m,(w.ft||(fc?fc.dataset.text:''))+' (card '+w.f+')','#c'+w.f);}
 line('Values',a.title||'(none: the FORMAT prints text only)');
}
document.querySelectorAll('a.w').forEach(function(a){
 a.addEventListener('focus',function(){show(a);});
 a.addEventListener('click',function(ev){if(box){ev.preventDefault();show(a);}});
});
var start=location.hash&&document.getElementById(location.hash.slice(1));
if(start&&start.classList.contains('w')){show(start);}
var q=document.getElementById('q'),n=document.getElementById('qn'),hits=[],at=-1;
if(q){document.querySelectorAll('.search').forEach(function(s){s.hidden=false;});
 q.addEventListener('input',function(){
  hits.forEach(function(e){e.classList.remove('hit')});hits=[];at=-1;
  var t=q.value.toUpperCase();if(t){document.querySelectorAll('pre.listing .c').forEach(function(c){
   if(c.textContent.toUpperCase().indexOf(t)>=0){c.classList.add('hit');hits.push(c);}});}
  n.textContent=t?hits.length+' card(s)':'';});
 q.addEventListener('keydown',function(ev){if(ev.key==='Enter'&&hits.length){ev.preventDefault();
  at=(at+1)%hits.length;var c=hits[at],s=c.closest('.scroll');if(s){s.scrollTop=c.offsetTop-s.clientHeight/3;}
  n.textContent=(at+1)+' of '+hits.length+' card(s)';}});
}
})();
"""


def _page(title: str, body: str, script: bool = True, data: dict | None = None) -> str:
    blob = ""
    if script:
        # JSON in a script element: "<" escaped, so no text can close the element
        text = json.dumps(data or {}, separators=(",", ":")).replace("<", "\\u003c")
        blob = (f'<script type="application/json" id="writes">{text}</script>\n'
                f"<script>{_SCRIPT}</script>\n")
    return ("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
            f'<meta http-equiv="Content-Security-Policy" content="{CSP}">\n'
            '<meta name="viewport" content="width=device-width, initial-scale=1">\n'
            f"<title>{_e(title)}</title>\n<style>{_STYLE}</style>\n</head>\n<body>\n"
            '<a class="skip" href="#main">Skip to the content</a>\n'
            f"{body}\n{blob}</body>\n</html>\n")


def _facts(facts: dict) -> str:
    rows = "".join(f"<dt>{_e(k)}</dt><dd>{_e(v)}</dd>" for k, v in facts.items())
    return f'<dl class="facts">{rows}</dl>'


def _nav(items: list[tuple[str, str]]) -> str:
    links = "".join(f'<li><a href="#{_e(i)}">{_e(t)}</a></li>' for i, t in items)
    return f'<nav aria-label="Parts of the page"><ul>{links}</ul></nav>'


# ------------------------------------------------------------------ the printout's forms


def _ruler() -> str:
    tens = "".join(f"{k:<10}" for k in range(1, POSITIONS // 10 + 1))
    marks = "".join("+" if k % 5 == 0 and k % 10 else "|" if k % 10 == 0 else "."
                    for k in range(1, POSITIONS + 1))
    return (f'<div class="ruler" aria-hidden="true"> {" " * 9}{tens}\n {marks}</div>')


def _values(w: WriteStatement | None, values: tuple) -> str:
    """The values of a WRITE's list, named as punched (``VVA = -58.60261562435258``)."""
    if w is not None and len(w.names) == len(values):
        return ", ".join(f"{n} = {v!r}" for n, v in zip(w.names, values))
    return ", ".join(repr(v) for v in values)


def printout(section: PrintedSection, program: Program, k: int) -> str:
    """The records of ``section`` on their forms, each inside the link to the WRITE that
    printed it (``k``: the section's number, for the links' ids)."""
    records, writes = section.records, section.writes
    owner: list[int | None] = [None] * len(records)  # the write that printed each record
    for n, w in enumerate(writes):
        end = writes[n + 1][0] if n + 1 < len(writes) else len(records)
        for i in range(w[0], end):
            owner[i] = n
    out: list[str] = []
    forms, lines, linked = 0, 0, None  # forms opened, lines on this form, the open link's write
    for i, rec in enumerate(records):
        cc, n = rec[:1], owner[i]
        if forms == 0 or (cc == "1" and lines > 0):  # a new form
            if linked is not None:
                out.append("</a>")
            if forms:
                out.append("</pre>")
            forms, lines, linked = forms + 1, 0, None
            out.append(f'<pre class="form" aria-label="form {forms}">')
        if n != linked:
            if linked is not None:
                out.append("</a>")
            linked = n
            if n is not None:
                first, unit, card, fmt, values = writes[n]
                anchor = f' id="p{k}-{first + 1}"' if i == first else ""
                shown = _values(program.writes.get((unit, card)), values)
                title = f' title="{_e(shown)}"' if shown else ""
                out.append(f'<a class="w" href="#c{card}"{anchor}{title}>')
        if cc == "0":  # a blank line first (at the top of a form: an empty line)
            out.append("\n\n" if lines else '<span class="b"></span>\n')
            lines += 1
        elif lines and cc != "+":  # the next line ("+": over the line before)
            out.append("\n")
        out.append(f'<span class="{"r o" if cc == "+" else "r"}"><i>{_e(cc)}</i>'
                   f"{_e(rec[1:])}</span>")
        lines += 1
    if linked is not None:
        out.append("</a>")
    if forms:
        out.append("</pre>")
    return "".join(out)


def listing(program: Program) -> str:
    """The program's cards: card number, internal statement number, the card as punched."""
    lines = []
    width = len(str(max((c.number for c in program.cards), default=1)))
    for c in program.cards:
        isn = f"{c.isn:>4}" if c.isn is not None else " " * 4
        text = c.text.rstrip()
        lines.append(f'<span class="c" id="c{c.number}" data-text="{_e(text.strip())}">'
                     f"<b>{c.number:>{width}} {isn} </b>{_e(text)}</span>")
    return '<pre class="listing">' + "\n".join(lines) + "</pre>"


def _write_info(program: Program) -> dict:
    return {str(card): {"u": u, "t": w.text, "f": w.format_card, "m": w.fmt,
                        "ft": w.format_text}
            for (u, card), w in program.writes.items()}


# --------------------------------------------------------------------------- the outcome


def _outcome(result: dict | None, note: str | None, stop: dict | None = None) -> str:
    """The events, quantities (with their status) and ratings (with their evidence) of the
    summary's answer (:func:`~deck_emulator.present.answers.outcome_result`)."""
    from deck_emulator.engine.quantities import QUANTITIES
    from deck_emulator.engine.safety import CRITERIA, STANDARDS

    from .answers import compartment_words

    if result is None:
        return f'<p class="note">{_e(note or "No outcome.")}</p>'
    parts = [f'<p class="note">{_e(note)}</p>' if note else "",
             '<section aria-labelledby="events-h"><h3 id="events-h">Events, in time order</h3>']
    events = sorted(result["events"], key=lambda e: (e["time_s"] is None, e["time_s"] or 0))
    items = [f"<li>{_e(ev['sentence'])}"
             + (f" <span class=\"note\">(FORMAT {_e(ev['label'])})</span>" if ev.get("label")
                else "") + "</li>" for ev in events]
    if stop is not None:  # the last thing that happened: the stop, with its reason
        items.append(f"<li><strong>the run stopped</strong>, {_e(stop['when'])}, at "
                     f"{_e(stop['where'])}: {_e(stop['why'])}</li>")
    parts.append(f"<ol>{''.join(items)}</ol>" if items else "<p>No event.</p>")
    parts.append("</section>")
    missing = result.get("unavailable") or {}

    def rows(values: dict) -> str:
        out = []
        for name, v in values.items():
            q = QUANTITIES[name]
            status = ("computed" if v is not None else
                      f"no value: {missing[name]}" if name in missing else "no value")
            out.append(f'<tr><th scope="row">{_e(q.label)}</th><td><code>{_e(name)}</code></td>'
                       f'<td class="num">{_e(q.show(v))}</td><td>{_e(q.unit)}</td>'
                       f"<td>{_e(status)}</td></tr>")
        return "".join(out)

    head = ('<tr><th scope="col">quantity</th><th scope="col">name</th><th scope="col">'
            'value</th><th scope="col">unit</th><th scope="col">status</th></tr>')
    parts.append('<section aria-labelledby="q-h"><h3 id="q-h">Quantities</h3>'
                 f"<table><thead>{head}</thead><tbody>{rows(result['quantities'])}"
                 f"{rows(result['occupant_risk'] or {})}</tbody></table>")
    if missing:
        parts.append("<p>No value and no rating: " + "; ".join(
            f"<code>{_e(k)}</code>: {_e(v)}" for k, v in missing.items()) + "</p>")
    parts.append("</section>")
    ratings = result.get("ratings")
    parts.append('<section aria-labelledby="r-h"><h3 id="r-h">Ratings, with their evidence</h3>')
    if not ratings:
        parts.append('<p class="note">No rating: the run gives no occupant-risk reading to '
                     "rate.</p>")
    else:
        comp = ratings["occupant_compartment"]
        parts.append(f"<p><strong>Occupant compartment:</strong> {_e(compartment_words(comp))}"
                     f"<br><span class=\"note\">{_e(comp['reason'])}</span></p>")
        crit = result.get("criteria") or {}
        body = []
        for name, r in ratings.items():
            if name == "occupant_compartment":
                continue
            q = QUANTITIES[name]
            for key, verdict in r["verdicts"].items():
                c = crit.get(key, {})
                good = verdict in ("preferred", "acceptable")
                body.append(
                    f'<tr><th scope="row">{_e(q.label)}</th>'
                    f'<td class="num">{_e(q.show(r["value"]))}'
                    f" {_e(q.unit)}</td><td>{_e(STANDARDS[CRITERIA[key].standard].name)}</td>"
                    f"<td>{_e(c.get('limit', ''))}</td><td class=\"verdict-"
                    f"{'ok' if good else 'bad'}\">{_e(verdict)}</td>"
                    f"<td>{_e(r['reason'])}<br><span class=\"note\">{_e(c.get('source', ''))}"
                    "</span></td></tr>")
        parts.append('<table><thead><tr><th scope="col">reading</th><th scope="col">value</th>'
                     '<th scope="col">standard</th><th scope="col">limit</th>'
                     '<th scope="col">verdict</th><th scope="col">evidence, source</th></tr>'
                     f"</thead><tbody>{''.join(body)}</tbody></table>")
    parts.append("</section>")
    return "".join(parts)


def pictures(outcome) -> tuple[list[tuple[str, str]], str | None]:
    """The side and plan views and the pulse of ``outcome`` as inline SVG ((caption, svg)
    pairs), with matplotlib's SVG backend; without the [plot] extra none, and the note
    saying so."""
    if importlib.util.find_spec("matplotlib") is None:
        return [], "No pictures: matplotlib is not installed (pip install 'deck_emulator[plot]')."
    if outcome is None or len(getattr(outcome, "t", ())) == 0:
        return [], "No pictures: the run recorded no trajectory to draw."
    import matplotlib

    from . import plot

    made = []
    for k, (caption, draw) in enumerate((
            ("The post and the car seen from the side", lambda: plot.figure_trajectory(
                outcome, "side")),
            ("The post and the car seen from above (plan)", lambda: plot.figure_trajectory(
                outcome, "plan")),
            ("The pulse: the car's deceleration and speed over the contact",
             lambda: plot.figure_pulse([outcome])))):
        with matplotlib.rc_context({"svg.fonttype": "none", "svg.hashsalt": f"dossier{k}"}):
            fig = draw()
            buf = io.StringIO()
            fig.savefig(buf, format="svg", metadata={"Date": None})
        svg = buf.getvalue()
        svg = _own_ids(svg[svg.index("<svg"):], f"fig{k}-")
        svg = svg.replace("<svg ", f'<svg role="img" aria-label="{_e(caption)}" ', 1)
        made.append((caption, svg))
    return made, None


def _own_ids(svg: str, prefix: str) -> str:
    """An SVG's ids (and the references to them) prefixed: several inline SVGs in one page
    whose ids would otherwise repeat (matplotlib names each figure's parts alike)."""
    import re

    ids = set(re.findall(r'\bid="([^"]+)"', svg))
    if not ids:
        return svg
    names = "|".join(re.escape(i) for i in sorted(ids, key=len, reverse=True))
    svg = re.sub(rf'\bid="({names})"', lambda m: f'id="{prefix}{m.group(1)}"', svg)
    return re.sub(rf'(["(])#({names})([")])', lambda m: f"{m.group(1)}#{prefix}{m.group(2)}"
                  f"{m.group(3)}", svg)


def _pictures_html(made: list[tuple[str, str]], note: str | None) -> str:
    if note:
        return f'<p class="note">{_e(note)}</p>'
    return "".join(f"<figure>{svg}<figcaption>{_e(caption)}</figcaption></figure>"
                   for caption, svg in made)


# ------------------------------------------------------------------------------- run page


def run_page(*, name: str, facts: dict, program: Program, sections: list[PrintedSection],
             stop: dict | None = None, result: dict | None = None,
             outcome_note: str | None = None, made_pictures=((), None)) -> str:
    """The page of ``run SOURCE --html``: the stop (if the run stopped) and the provenance
    first, the outcome, the pictures, then the printout beside the listing."""
    parts = ['<header class="top"><h1>Dossier of a run: ' + _e(name) + "</h1>"]
    nav = [("provenance", "Provenance"), ("outcome", "Events, quantities, ratings"),
           ("pictures", "Pictures")]
    nav += [(f"printout-{k}", f"Printout{f' {k}' if len(sections) > 1 else ''}")
            for k in range(1, len(sections) + 1)]
    nav += [("listing", "Listing")]
    parts.append(_nav(nav))
    if stop is not None:
        where = stop.get("section")
        parts.append('<div class="stop" role="alert"><strong>The run stopped.</strong> '
                     + (f"Section {_e(where)}: " if where else "")
                     + f"at {_e(stop['where'])}, {_e(stop['when'])}: {_e(stop['why'])}. "
                     "The records printed until then are below, as printed"
                     + (f' (<a href="#p{len(sections)}-{sections[-1].writes[-1][0] + 1}">the '
                        "last WRITE's records</a>)" if sections and sections[-1].writes else "")
                     + ".</div>")
    parts.append("</header>\n<main id=\"main\">")
    parts.append('<section id="provenance" aria-labelledby="prov-h"><h2 id="prov-h">'
                 f"Provenance</h2>{_facts(facts)}</section>")
    parts.append('<section id="outcome" aria-labelledby="out-h"><h2 id="out-h">Events, '
                 f"quantities and ratings</h2>{_outcome(result, outcome_note, stop)}</section>")
    parts.append('<section id="pictures" class="pictures" aria-labelledby="pic-h">'
                 f'<h2 id="pic-h">Pictures</h2>{_pictures_html(*made_pictures)}</section>')
    parts.append('<section aria-labelledby="pl-h"><h2 id="pl-h">The printout beside the '
                 "listing that printed it</h2>"
                 '<p class="note">Each record links to the WRITE statement that printed it '
                 "(its FORMAT and the values of its list are in the link's title; with the "
                 "script, in the box above the listing). Column 1, in grey, is the carriage "
                 "control: 1 a new form, 0 a blank line first, + over the line before.</p>"
                 '<div class="beside"><div>')
    for k, s in enumerate(sections, start=1):
        parts.append(f'<section id="printout-{k}" aria-labelledby="pr{k}-h">'
                     f'<h3 id="pr{k}-h">Printout'
                     f'{f" {k} of {len(sections)}" if len(sections) > 1 else ""}: '
                     f"{_e(s.deck)}</h3><p class=\"note\">{_e(s.settings)}; "
                     f"{len(s.records):,} records</p>"
                     f'<div class="paper">{_ruler()}{printout(s, program, k)}</div></section>')
    parts.append('</div><div class="listcol" id="listing" aria-labelledby="lst-h">'
                 f'<h3 id="lst-h">Listing: {_e(program.title)}</h3>'
                 '<div class="search" hidden><label for="q">Search the listing</label> '
                 '<input id="q" type="search" autocomplete="off"> <span id="qn" '
                 'aria-live="polite"></span></div>'
                 '<div class="box" id="detail" aria-live="polite"><p class="note">Focus or '
                 "click a record to see the statement that printed it.</p></div>"
                 '<div class="scroll" tabindex="0" aria-label="the listing\'s cards">'
                 '<p class="note" style="margin:.2rem .4rem">card, internal statement number '
                 "(ISN), the card as punched</p>"
                 f"{listing(program)}</div></div></div></section></main>")
    return _page(f"{name}: dossier of a run", "".join(parts), data=_write_info(program))


# --------------------------------------------------------------------------- compare page


def compare_page(*, a: str, b: str, counts_line: str, verdict_line: str, found,
                 records_a, records_b, lined_up) -> str:
    """The page of ``compare A B --html``: the counts first, then the findings, then the two
    printouts aligned record by record (``lined_up``: pairs of indexes into ``records_a`` and
    ``records_b``, None on the side that lacks the record), each row coloured by what the
    comparison found for it."""
    status: dict[tuple[str, int], str] = {}
    for d in found.differences:
        status[("A", d.record_a)] = status[("B", d.record_b)] = "differ"
    for d in found.damaged:
        status[(d.printout, d.record)] = d.reading if d.reading == "unreadable" else "damaged"
    for m in found.missing:
        status[(m.printout, m.record)] = "missing"
    counts = found.counts()
    parts = ['<header class="top"><h1>Comparison of two printouts</h1>',
             _nav([("counts", "Counts"), ("findings", "Findings"), ("aligned", "Aligned")]),
             "</header><main id=\"main\">",
             f'<section id="counts" aria-labelledby="c-h"><h2 id="c-h">Counts</h2>'
             f"<p><strong>{_e(counts_line)}</strong></p>"
             f"{_facts({'A': a, 'B': b})}<table class=\"counts\"><tbody>"
             + "".join(f'<tr><th scope="row">{_e(k.replace("_", " "))}</th>'
                       f'<td class="num">{v:,}</td></tr>' for k, v in counts.items())
             + f"</tbody></table><p>{_e(verdict_line)}</p></section>",
             '<section id="findings" aria-labelledby="f-h"><h2 id="f-h">Findings</h2>']
    for title, kind in (("Differences", found.differences), ("Damaged or unreadable",
                                                             found.damaged),
                        ("Missing", found.missing)):
        parts.append(f"<h3>{title} ({len(kind):,})</h3>")
        if kind:
            parts.append("<ul>" + "".join(f"<li><code>{_e(f.line())}</code></li>"
                                          for f in kind) + "</ul>")
    parts.append("</section>")
    rows = []
    for i, j in lined_up:
        x = records_a[i] if i is not None else None
        y = records_b[j] if j is not None else None
        marks = [status.get(("A", x.line)) if x else None, status.get(("B", y.line)) if y
                 else None]
        if x is None or y is None:
            marks.append("missing")
        cls = next((m for m in ("differ", "unreadable", "missing", "damaged") if m in marks),
                   "equal")
        rows.append(f'<tr class="{cls}"><td class="num">{x.line if x else ""}</td>'
                    f"<td>{_e(x.text) if x else ''}</td>"
                    f'<td class="num">{y.line if y else ""}</td>'
                    f"<td>{_e(y.text) if y else ''}</td><td>{cls}</td></tr>")
    parts.append('<section id="aligned" aria-labelledby="al-h"><h2 id="al-h">The two '
                 "printouts, record by record</h2><p class=\"note\">Rows coloured: differ "
                 "(red), damaged (yellow), unreadable (orange), in one printout only (violet)."
                 '</p><table class="aligned"><thead><tr><th scope="col">line of A</th>'
                 '<th scope="col">A</th><th scope="col">line of B</th><th scope="col">B</th>'
                 f'<th scope="col">found</th></tr></thead><tbody>{"".join(rows)}</tbody>'
                 "</table></section></main>")
    return _page(f"compare {a} {b}", "".join(parts), script=False)


# ------------------------------------------------------------------------------ diff page


def diff_page(*, name: str, text: str, data: dict, settings: dict,
              stopped: str | None = None) -> str:
    """The page of ``diff SOURCE --html``: the emulator and the core side by side (the diff's
    own ``emulator`` and ``core`` answers, and core minus emulator where both are numbers),
    the convergence rows, the table as the command prints it, and its settings."""
    parts = [f'<header class="top"><h1>The emulator and the core on {_e(name)}</h1>',
             _nav([("side", "Side by side"), ("rows", "Convergence"), ("table", "As printed"),
                   ("settings", "Settings")])]
    if stopped:
        parts.append('<div class="stop" role="alert"><strong>A run stopped.</strong> '
                     f"{_e(stopped)}</div>")
    parts.append('</header><main id="main">')
    emu, core = data.get("emulator") or {}, data.get("core") or {}
    rows = []
    for key in dict.fromkeys([*emu, *core]):
        x, y = emu.get(key), core.get(key)
        if isinstance(x, dict) or isinstance(y, dict):  # the points at the hit, by axis
            for point in dict.fromkeys([*(x or {}), *(y or {})]):
                px, py = (x or {}).get(point), (y or {}).get(point)
                for axis, label in enumerate(("XL", "YL", "ZL")):
                    vx = px[axis] if px else None
                    vy = py[axis] if py else None
                    rows.append((f"{key} {point} {label}", vx, vy))
        else:
            rows.append((key, x, y))
    body = []
    for key, x, y in rows:
        numbers = all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in (x, y))
        delta = _cell(y - x) if numbers else ("same" if x == y else "differ")
        cls = "" if numbers or x == y else ' class="differ"'
        body.append(f'<tr{cls}><th scope="row"><code>{_e(key)}</code></th>'
                    f'<td class="num">{_e(_cell(x))}</td><td class="num">{_e(_cell(y))}</td>'
                    f'<td class="num">{_e(delta)}</td></tr>')
    parts.append('<section id="side" aria-labelledby="sd-h"><h2 id="sd-h">The emulator and '
                 'the core, side by side</h2><table class="aligned"><thead><tr><th scope="col">'
                 'what</th><th scope="col">emulator</th><th scope="col">core</th>'
                 '<th scope="col">core &minus; emulator</th></tr></thead><tbody>'
                 f"{''.join(body)}</tbody></table></section>")
    parts.append('<section id="rows" aria-labelledby="rw-h"><h2 id="rw-h">Convergence as the '
                 "step is halved</h2>")
    for key, value in data.items():
        if isinstance(value, list) and value and all(isinstance(r, dict) for r in value):
            cols = list(dict.fromkeys(c for r in value for c in r))
            head = "".join(f'<th scope="col">{_e(c)}</th>' for c in cols)
            body_ = "".join("<tr>" + "".join(f"<td>{_e(_cell(r.get(c)))}</td>" for c in cols)
                            + "</tr>" for r in value)
            parts.append(f'<div class="paper"><table><caption>{_e(key)}</caption><thead><tr>'
                         f"{head}</tr></thead><tbody>{body_}</tbody></table></div>")
    rest = {k: v for k, v in data.items() if k not in ("emulator", "core")
            and not (isinstance(v, list) and v and all(isinstance(r, dict) for r in v))}
    parts.append(f"{_facts({k: _cell(v) for k, v in rest.items()})}</section>")
    parts.append('<section id="table" aria-labelledby="t-h"><h2 id="t-h">The table, as '
                 f'<code>diff</code> prints it</h2><pre class="listing">{_e(text)}</pre>'
                 "</section>")
    parts.append(f'<section id="settings" aria-labelledby="s-h"><h2 id="s-h">Settings</h2>'
                 f"{_facts({k: _cell(v) for k, v in settings.items()})}</section></main>")
    return _page(f"diff {name}", "".join(parts), script=False)


def _cell(v) -> str:
    if v is None:
        return "-"
    if isinstance(v, float):
        return f"{v:.6g}"
    if isinstance(v, (list, tuple)):
        return ", ".join(_cell(x) for x in v)
    if isinstance(v, dict):
        return "; ".join(f"{k} {_cell(x)}" for k, x in v.items())
    return str(v)
