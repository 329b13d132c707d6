#!/usr/bin/env python3
"""Writes the tables of docs/performance.md from what
scripts/performance_tables.sh saved in its output directory: `evsim bench`
text, `evsim bench accuracy --csv`, Google Benchmark JSON, the summaries of
scripts/step_summary.py, scripts/effects_table.py's CSV, and the outputs of
scripts/env_benchmark.py and scripts/node_benchmark.py. One table per
question; a table whose outputs are missing is left out (with a note).

Usage: scripts/performance_markdown.py OUT_DIR > OUT_DIR/tables.md
Python 3 standard library only.
"""
import csv
import json
import os
import re
import sys

OUT = "."
CMD_BENCH = "build/ws/devel/lib/endovascular_sim/evsim"
MISSING = []


def path(name):
    return os.path.join(OUT, name)


def read(name):
    try:
        with open(path(name), encoding="utf-8") as f:
            return f.read()
    except OSError:
        MISSING.append(name)
        return None


def table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "| " + " | ".join("---" for _ in header) + " |"]
    lines += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(lines)


def section(title, command, body, note="", intro="", level=2):
    print("#" * level + " " + title + "\n")
    if intro:
        print(intro)
    print("```bash\n" + command.strip() + "\n```\n")
    if body:
        print(body + "\n")
    if note:
        print(note + "\n")


def num(x, digits=3):
    return ("%." + str(digits) + "f") % x


def thousands(n):
    return "{:,}".format(int(n))


def g3(x):
    """Three significant digits, without an exponent from 1e-4 to 1e6."""
    if x == 0 or 1e-4 <= abs(x) < 1e6:
        return "%.0f" % float("%.3g" % x) if abs(x) >= 1000 else "%.3g" % x
    return "%.2g" % x


# ---- evsim bench text ----------------------------------------------------

PHASE = re.compile(r"^\s+(free|contact|inserted|whole)\s+(\d+)(?:\s+([0-9.]+)\s+([0-9.]+)\s+([0-9.]+)"
                   r"\s+([0-9.]+)\s+([0-9.inf]+))?\s*$", re.M)


def bench(name):
    """The first block of an `evsim bench` output: phases, counts."""
    text = read(name)
    if text is None:
        return None
    r = {"text": text}
    m = re.search(r"^scene (\S+): (\d+) device\(s\), (\d+) elements, effects \[([^\]]*)\]; (\d+) steps of "
                  r"([0-9.]+) ms", text, re.M)
    if m:
        r.update(scene=m.group(1), devices=int(m.group(2)), elements=int(m.group(3)),
                 effects=m.group(4), steps=int(m.group(5)), dt=float(m.group(6)))
    head = text.split("steps with >=")[0].split("windows:")[0]
    for p in PHASE.finditer(head):
        r[p.group(1)] = None if p.group(3) is None else {
            "steps": int(p.group(2)), "median": float(p.group(3)), "mean": float(p.group(4)),
            "p99": float(p.group(5)), "worst": float(p.group(6)), "rtf": float(p.group(7))}
    m = re.search(r"LCP rows: median (\d+)\s+max (\d+);\s+steps subdivided (\d+);\s+most activation loops"
                  r" (\d+);\s+steps asleep (\d+)", head)
    if m:
        r.update(rows_median=int(m.group(1)), rows_max=int(m.group(2)), halved=int(m.group(3)),
                 loops_max=int(m.group(4)), asleep=int(m.group(5)))
    m = re.search(r"loops after the first (\d+), for the rows found late: wall (\d+), pair (\d+), lumen (\d+)",
                  head)
    if m:
        r.update(late_loops=int(m.group(1)), late_wall=int(m.group(2)), late_pair=int(m.group(3)),
                 late_lumen=int(m.group(4)))
    m = re.search(r"steps with >= (\d+) LCP rows: (\d+) of (\d+)", text)
    if m:
        r["many_rows"] = (int(m.group(1)), int(m.group(2)))
        tail = text.split("steps with >=")[1]
        w = re.search(r"^\s+whole\s+\d+\s+([0-9.]+)", tail, re.M)
        r["many_rows_median"] = float(w.group(1)) if w else None
    m = re.search(r"against (\S+) .*: median ([0-9.]+) ms", text)
    if m:
        r["against"] = (m.group(1), float(m.group(2)))
    return r


def fmt_phase(p, p99=True):
    if not p:
        return "—"
    return num(p["median"]) + (" / " + num(p["p99"], 2) if p99 else "")


def scenes_table():
    nav = ["carotid", "carotid_selective", "carotid_catheter", "network", "aneurysm", "aneurysm_coiling",
           "patient_example"]
    stab = ["dead_end", "tortuous", "large_step", "aneurysm_packed"]
    rows = []
    for s in nav + stab + ["aneurysm_packed_full", "carotid_no_sleep"]:
        b = bench("bench_%s.txt" % s)
        if not b or "whole" not in b:
            continue
        label = {"aneurysm_packed_full": "`aneurysm_packed`, t = 14.4–15.3 s (the dome full)",
                 "carotid_no_sleep": "`carotid --no-sleep`"}.get(s, "`%s`" % s)
        w = b["whole"]
        rows.append([label, "%d, %d" % (b["devices"], b["elements"]), num(b["dt"], 0),
                     fmt_phase(b.get("free"), False), fmt_phase(b.get("contact")),
                     fmt_phase(b.get("inserted")),
                     "%s / %s / %s" % (num(w["median"]), num(w["p99"], 2), num(w["worst"], 2)),
                     num(w["rtf"], 2), "%d / %d" % (b["rows_median"], b["rows_max"]),
                     thousands(b["late_loops"]), b["halved"], thousands(b["asleep"])])
    body = table(["scene", "devices, elements", "step [ms]", "free: median", "contact: median / p99",
                  "inserted: median / p99", "whole: median / p99 / worst", "RTF", "LCP rows: median / max",
                  "loops after the first", "halved steps", "steps asleep"], rows)
    notes = []
    p = bench("bench_aneurysm_packed.txt")
    f = bench("bench_aneurysm_packed_full.txt")
    for b, what in ((p, "whole procedure"), (f, "t = 14.4–15.3 s")):
        if b and b.get("many_rows") and b.get("against"):
            notes.append("`aneurysm_packed` (%s): %d steps with ≥ %d LCP rows, median %s ms; against a run of "
                         "`carotid` within the same command, the whole median is %.1f× `carotid`'s and those "
                         "steps' %.1f×."
                         % (what, b["many_rows"][1], b["many_rows"][0], num(b["many_rows_median"]),
                            b["whole"]["median"] / b["against"][1], b["many_rows_median"] / b["against"][1]))
    return body, " ".join(notes)


# ---- the autopilot --------------------------------------------------------

SUMMARY = re.compile(r"(\d+) steps, ([0-9.]+) s simulated; step median ([0-9.]+) p99 ([0-9.]+) worst ([0-9.]+)"
                     r" ms; RTF ([0-9.inf]+); mean loops ([0-9.]+), mean contacts ([0-9.]+)")


def procedures_table():
    rows = []
    for t in ["left_common_carotid", "left_subclavian", "right_common_carotid", "right_subclavian"]:
        s = read("navigate_%s_summary.txt" % t)
        if not s:
            continue
        m = SUMMARY.search(s)
        if not m:
            continue
        try:
            nav = json.loads((read("navigate_%s.txt" % t) or "{}").strip().splitlines()[-1])
        except (ValueError, IndexError):
            nav = {}
        rows.append(["`arch_to_%s`" % t, "yes" if nav.get("reached") else "no", m.group(2),
                     "%s / %s / %s" % (m.group(3), m.group(4), m.group(5)), m.group(6), m.group(7), m.group(8)])
    return table(["scene", "reached", "simulated [s]", "step: median / p99 / worst [ms]", "RTF",
                  "mean loops", "mean contacts"], rows)


# ---- effects ---------------------------------------------------------------

def effects_table():
    text = read("effects.csv")
    if text is None:
        return ""
    by_scene = {}
    for r in csv.DictReader(text.splitlines()):
        by_scene.setdefault(r["scene"], []).append(r)
    names = ["gravity", "subdivision", "device_contact", "friction", "blood_drag", "vessel_motion", "coaxial"]
    rows = []
    for scene, variants in by_scene.items():
        shipped = variants[0]
        cells = {}
        for v in variants[1:]:
            kind, effect = v["variant"].split(" ", 1)
            sign = "−" if kind == "without" else "+"
            if v["median_ms"]:
                cells[effect] = "%s %s / %s" % (sign, num(float(v["median_ms"])), num(float(v["p99_ms"]), 2))
            else:
                cells[effect] = "%s does not run" % sign
        rows.append(["`%s`" % scene, "%s / %s" % (num(float(shipped["median_ms"])), num(float(shipped["p99_ms"]), 2))]
                    + [cells.get(n, "") for n in names])
    return table(["scene", "as shipped"] + ["`%s`" % n for n in names], rows)


# ---- Google Benchmark ------------------------------------------------------

def gbench():
    text = read("stages.json")
    if text is None:
        return {}
    out = {}
    for b in json.loads(text)["benchmarks"]:
        if b.get("run_type") == "aggregate" and b.get("aggregate_name") != "median":
            continue
        out[b.get("run_name", b["name"])] = b
    return out


UNIT = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}


def secs(b):
    return b["cpu_time"] * UNIT[b["time_unit"]]


def t(x):
    if x is None:
        return ""
    if x >= 1e-3:
        return "%.3g ms" % (x * 1e3)
    if x >= 1e-6:
        return "%.3g µs" % (x * 1e6)
    return "%.3g ns" % (x * 1e9)


def family(g, name):
    """{argument: benchmark} of a family BM_NAME/ARG."""
    out = {}
    for k, b in g.items():
        parts = k.split("/")
        if parts[0] == name and len(parts) > 1 and parts[1].isdigit():
            out[int(parts[1])] = b
    return dict(sorted(out.items()))


def stages_tables(g):
    parts = []
    fm = family(g, "BM_FreeMotionStep")
    if fm:
        parts.append(("Free motion", "BM_FreeMotionStep",
                      table(["elements"] + [str(k) for k in fm], [["CPU time"] + [t(secs(b)) for b in fm.values()]]),
                      "One device's free motion: assembly of `A`, its factorisation, one solve; every node "
                      "free. In a scene only the inserted part costs this (elements the introducer holds "
                      "are not assembled)."))
    fg, fr = family(g, "BM_FieldAndGradient"), family(g, "BM_FirstRootQuery")
    if fg:
        rows = [[thousands(k), t(secs(b)), t(secs(fr[k])) if k in fr else ""] for k, b in fg.items()]
        build = g.get("BM_BuildNetworkScene")
        parts.append(("The vessel field", "BM_FieldAndGradient|BM_FirstRootQuery|BM_BuildNetworkScene",
                      table(["vessels", "field + gradient", "first-root query (0.5 mm step)"], rows)
                      + ("\n\nBuilding `network`'s 4,000 vessels and their cell grid "
                         "(`BM_BuildNetworkScene`): %s." % t(secs(build)) if build else ""),
                      "The field at query points inside the right common carotid near its wall, in "
                      "networks of generated vessels: flat in the vessel count, since a grid cell lists "
                      "only the segments whose support reaches it."))
    ch, bs, ss = family(g, "BM_DelassusChain"), family(g, "BM_DelassusBlockSolve"), family(g, "BM_DelassusSeparateSolves")
    if ch:
        rows = [[k, t(secs(b)), t(secs(bs[k])) if k in bs else "", t(secs(ss[k])) if k in ss else ""]
                for k, b in ch.items()]
        band = g.get("BM_DelassusBandFromFactor")
        sw, tr = family(g, "BM_DelassusSweep"), family(g, "BM_DelassusTrailingSolve")
        rows2 = [[k, t(secs(b)), t(secs(tr[k])) if k in tr else ""] for k, b in sw.items()]
        parts.append(("The Delassus operator", "BM_Delassus",
                      table(["rows c", "factor, band of A⁻¹ and its sweep", "block solve", "c separate solves"], rows)
                      + ("\n\nThe band of A⁻¹ from the factor alone (`BM_DelassusBandFromFactor`): %s; "
                         "then per row:\n\n" % t(secs(band)) if band else "\n\n")
                      + table(["rows c", "band sweep", "block solve from the rows' first node"], rows2),
                      "W = H A⁻¹ Hᵀ on a 200-element guidewire, c contact rows at random points with "
                      "normals across the wire (nearly dependent rows, as real contact sets are). Per "
                      "device and loop the solver takes the cheaper of the band of A⁻¹ and the block "
                      "solve ([design.md](design.md#linear-algebra))."))
    st, sl = family(g, "BM_SceneStatusMethod"), family(g, "BM_SceneSiconosLemke")
    if st:
        ks = list(st)
        parts.append(("The LCP: the status method against Siconos", "BM_SceneStatusMethod|BM_SceneSiconosLemke",
                      table(["rows c"] + [str(k) for k in ks],
                            [["status method (warm start)"] + [t(secs(st[k])) for k in ks],
                             ["Siconos Lemke"] + [t(secs(sl[k])) if k in sl else "" for k in ks],
                             ["ratio"] + ["%.0f×" % (secs(sl[k]) / secs(st[k])) if k in sl else "" for k in ks]]),
                      "LCPs saved from real steps (`aneurysm`, `dead_end`, `large_step`), the step whose "
                      "LCP is nearest each size; both solve to round-off (Siconos' natural-map residual)."))
    rows = []
    for name, label in (("BM_FrictionNewton", "Newton (Alart–Curnier, the default)"), ("BM_FrictionNsgs", "NSGS"),
                        ("BM_FrictionSiconosNsnAc", "Siconos `NSN_AC`")):
        b = g.get(name)
        if not b:
            continue
        per = b.get("per_problem")
        rows.append([label, t(per) if per else "", "%.4g" % b["steps_per_problem"] if b.get("steps_per_problem") else "",
                     "%d" % b["unsolved"] if "unsolved" in b else "",
                     "%.2g" % b["worst_residual"] if "worst_residual" in b else ""])
    if rows:
        parts.append(("Friction", "BM_Friction", table(["solver", "CPU time per problem", "iterations per problem",
                                                         "unsolved of 100", "worst residual"], rows),
                      "100 frictional problems of `carotid_catheter` (wall and lumen contacts, many "
                      "redundant), each from zero forces to a residual of 1e-10."))
    return parts


# ---- accuracy ----------------------------------------------------------------

KEY = {"solver": "contact.solver", "lcp_tolerance": "contact.tolerance", "friction_solver": "contact.friction_solver",
       "friction_tolerance": "contact.friction_tolerance", "penetration_tolerance": "contact.penetration_tolerance",
       "pair_tolerance": "contact.pair_tolerance", "activation_loops": "contact.max_activation_loops",
       "curvature_loops": "contact.curvature_loops", "lumen_tolerance": "contact.lumen_tolerance",
       "lumen_settle": "contact.lumen_settle", "subdivisions": "contact.max_subdivisions",
       "root_tolerance": "contact.root_tolerance", "elements": "elements per device", "time_step": "time_step",
       "baseline": "the scene as shipped"}


def schema_rows():
    """[(key, unit, default, range)] of the `contact.` keys, from `evsim schema`."""
    text = read("schema.md") or ""
    rows = []
    for line in text.splitlines():
        m = re.match(r"^\| `contact\.(\w+)` \| ([^|]*)\| ([^|]*)\| ([^|]*)\| ([^|]*)\|", line)
        if m:
            kind, unit, default, rng = (x.strip() for x in m.groups()[1:])
            rows.append((m.group(1), unit, default, rng or kind))
    return rows


# The sweep's knobs by scene key; the keys it does not vary are measured in
# the tables named here.
SWEPT = {"solver": "solver", "tolerance": "lcp_tolerance", "friction_solver": "friction_solver",
         "friction_tolerance": "friction_tolerance", "penetration_tolerance": "penetration_tolerance",
         "pair_tolerance": "pair_tolerance", "max_activation_loops": "activation_loops",
         "curvature_loops": "curvature_loops", "lumen_tolerance": "lumen_tolerance",
         "lumen_settle": "lumen_settle", "max_subdivisions": "subdivisions", "root_tolerance": "root_tolerance"}
ELSEWHERE = {
    "max_iterations": "a solver's own limit (0: automatic)",
    "contact_spacing": "[options over whole procedures](#options-over-whole-procedures)",
    "keep_gap": "[options over whole procedures](#options-over-whole-procedures)",
    "wall_curvature": "[options over whole procedures](#options-over-whole-procedures)",
    "predict_first_iterate": "[options over whole procedures](#options-over-whole-procedures), "
                             "[paired](#options-paired-aneurysm)",
    "element_pairs": "[paired](#options-paired-aneurysm)",
    "new_pair_overlap": "[paired](#options-paired-aneurysm_packed)"}


def accuracy_table(scenes):
    data = {}
    for s in scenes:
        text = read("accuracy_%s.csv" % s)
        if text is None:
            continue
        for r in csv.DictReader(text.splitlines()):
            data.setdefault(r["knob"], {}).setdefault(s, []).append(r)
    present = [s for s in scenes if any(s in v for v in data.values())]

    def cells(knob):
        out = []
        for s in present:
            rs = data.get(knob, {}).get(s)
            if not rs:
                out += ["", ""]
                continue
            out.append("; ".join("%.3g" % float(r["cost"]) + (" (%s rejected)" % r["rejected"]
                                                            if int(r["rejected"]) else "") for r in rs))
            out.append("; ".join("%.3g" % (float(r["error_m"]) * 1e3) for r in rs))
        return out

    def settings(knob):
        for s in present:
            rs = data.get(knob, {}).get(s)
            if rs:
                return "; ".join(r["setting"] for r in rs)
        return ""

    rows = [["the scene as shipped", "", "", "", ""] + cells("baseline")]
    for key, unit, default, rng in schema_rows():
        knob = SWEPT.get(key)
        if knob and knob in data:
            rows.append(["`%s`" % key, unit, default, rng, settings(knob)] + cells(knob))
        else:
            rows.append(["`%s`" % key, unit, default, rng, ELSEWHERE.get(key, "")] + [""] * (2 * len(present)))
    if "elements" in data:
        rows.append(["elements per device", "", "the scene's", "", "0.5×; 1.5×; 2×"] + cells("elements"))
    if "time_step" in data:
        rows.append(["`time_step`", "s", "the scene's", "[1e-6, 0.04]", "0.5×; 2×; 5×"] + cells("time_step"))
    head = ["option", "unit", "default", "range", "settings"]
    for s in present:
        head += ["`%s` cost [s/s]" % s, "tip error [mm]"]
    deepest = []
    for s in present:
        for r in data.get("penetration_tolerance", {}).get(s, []):
            deepest.append("%s %s m: %.3g µm" % (s, r["setting"], float(r["max_penetration_m"]) * 1e6))
    note = ("The deepest penetration after any step follows `penetration_tolerance`: "
            + "; ".join(deepest) + ".") if deepest else ""
    return table(head, rows), note


def alone_tables():
    rows = []
    for what, unit in (("beam", "ms a free step"), ("root", "µs a query")):
        text = read("accuracy_%s.csv" % what)
        if text is None:
            continue
        rs = list(csv.DictReader(text.splitlines()))
        if what == "beam":
            rows.append(["beam elements (100 mm cantilever, PL²/EI = 5, against 800)",
                         "; ".join(r["setting"] for r in rs), "; ".join(g3(float(r["error_m"]) * 1e6) for r in rs)
                         + " µm", "; ".join("%.2g" % float(r["cost"]) for r in rs) + " " + unit])
        else:
            rows.append(["`contact.root_tolerance` [m] (2,000 segments through the carotid wall, against 1e-13 m)",
                         "; ".join(r["setting"] for r in rs), "; ".join("%.2g" % float(r["error_m"]) for r in rs)
                         + " m", "; ".join("%.3g" % float(r["cost"]) for r in rs) + " " + unit])
    return table(["what", "settings", "error", "cost"], rows)


# ---- option variants ---------------------------------------------------------

WINDOW = re.compile(r"^\s+(\S.*?)\s+(\d+)\s+(\d+)\s+(\d+)\s+(\d+)\s+([0-9.]+)\s+(\d+)\s+([0-9.]+)\s+([0-9.]+)\s+"
                    r"([0-9.]+)\s+([0-9.]+)\s*$", re.M)


def windows_table(name, labels):
    text = read(name)
    if text is None:
        return "", ""
    head = re.search(r"windows: (\d+) states from t = ([0-9.]+) to ([0-9.]+) s, (\d+) steps from each", text)
    rows = []
    for m in WINDOW.finditer(text):
        label = m.group(1)
        base = os.path.basename(label)
        label = labels.get(base.split(".", 1)[1].rsplit(".yaml", 1)[0] if base.endswith(".yaml") else "scene",
                           label) if base.endswith(".yaml") else "the scene as shipped"
        rows.append([label, thousands(m.group(2)), "%s / %s" % (thousands(m.group(3)), thousands(m.group(4))),
                     m.group(6), m.group(7), m.group(8), m.group(9), m.group(10), m.group(11)])
    what = ("%s states from t = %s to %s s, %s steps from each" % head.groups()) if head else ""
    return table(["variant", "loops after the first", "late wall / pair rows", "rows (mean)", "halved",
                  "deepest [µm]", "median [ms]", "mean [ms]", "p99 [ms]"], rows), what


def options_whole_table():
    rows = []
    for scene, name, label in (
            ("carotid", "scene", "`carotid` as shipped"),
            ("carotid", "spacing_0.5mm", "`contact_spacing` 0.5 mm"),
            ("carotid", "spacing_2mm", "`contact_spacing` 2 mm"),
            ("carotid", "keep_gap_10um", "`keep_gap` 10 µm"),
            ("carotid", "predict", "`predict_first_iterate` true"),
            ("carotid", "no_wall_curvature", "`wall_curvature` false"),
            ("network", "scene", "`network` as shipped (`keep_gap` 10 µm)"),
            ("network", "keep_gap_0", "`keep_gap` 0")):
        b = bench("option_%s.%s.txt" % (scene, name))
        if not b or not b.get("whole"):
            continue
        w = b["whole"]
        rows.append([label, "%s / %s" % (num(w["median"]), num(w["p99"], 2)), num(w["rtf"], 2),
                     "%d / %d" % (b["rows_median"], b["rows_max"]), thousands(b["late_loops"]), b["halved"]])
    return table(["variant", "whole: median / p99 [ms]", "RTF", "LCP rows: median / max", "loops after the first",
                  "halved steps"], rows)


def machine():
    text = read("machine.txt") or ""
    info = dict(l.split(": ", 1) for l in text.splitlines() if ": " in l)
    return info


def main(argv):
    global OUT
    if len(argv) != 2:
        sys.exit(__doc__)
    OUT = argv[1]
    e = CMD_BENCH
    m = machine()
    print("# Performance\n")
    print("What the simulator costs, as tables that one command regenerates:\n")
    print("```bash\nbash scripts/performance_tables.sh   # writes build/performance/tables.md, this page\n```\n")
    print("It runs every measurement below, keeps the raw outputs in "
          "`build/performance/`, and writes the tables (`scripts/performance_markdown.py`); "
          "`--skip PART,...` reuses a part's saved outputs. Beside each table is the command "
          "that measures it alone. Why the mechanisms behind these figures exist, with and "
          "without them: [design.md](design.md).\n")
    print("Machine: %s, %s cores, %s; %s; Release build%s. Measured on %s, %s: figures "
          "are as they came, and a loaded machine runs slower, so compare figures within a "
          "table, where they come from one run.\n" % (
              m.get("cpu", "?"), m.get("cores", "?"), m.get("memory", "?"), m.get("os", "?"),
              " for x86-64-v3 (AVX2, FMA)", m.get("date", "?"), m.get("load", "")))
    body, note = scenes_table()
    section("Whole procedures", "for s in carotid carotid_selective carotid_catheter network aneurysm aneurysm_coiling \\\n"
            "         patient_example dead_end tortuous large_step; do %s bench $s; done\n"
            "%s bench aneurysm_packed --min-rows 300 --against carotid\n"
            "%s bench aneurysm_packed --warmup 14400 --steps 900 --min-rows 300 --against carotid\n"
            "%s bench carotid --no-sleep" % (e, e, e, e), body, note,
            "`evsim bench SCENE` steps the scene from t = 0 to its `duration` on one core and "
            "sorts every step into a phase: `free` (before the first contact), `contact` (in "
            "contact while a drive moves a device), `inserted` (in contact with every drive at "
            "rest). Times are wall time per step [ms]; RTF is simulated time over wall time. "
            "The navigation scenes (the first seven) aim at a whole-procedure median of at most "
            "a quarter of the step and a p99 below it. `--no-sleep` solves every step, also "
            "once the scene is at rest (scene key `sleep`).")
    section("The autopilot's procedures",
            "%s navigate arch_to_right_subclavian --timeout 30 --quiet --steps-json steps.json  # and each target\n"
            "/usr/bin/python3 scripts/step_summary.py steps.json" % e, procedures_table(), "",
            "The autopilot from the femoral access to each arch target "
            "([navigation.md](navigation.md)), every step of the run, frictionless.")
    section("The node", "source build/ws/devel/setup.bash   # (bash scripts/build.sh builds the node)\n"
            "/usr/bin/python3 scripts/node_benchmark.py\n"
            "/usr/bin/python3 scripts/node_benchmark.py --xray carotid network", node_tables(),
            "The publisher never waits for a step (it publishes the last step's copy), so frames "
            "keep their rate even when the simulation falls behind real time; `/clock` and every "
            "stamp then follow the simulation ([ros_interface.md](ros_interface.md)). What an "
            "X-ray frame costs: [sensors.md](sensors.md).",
            "`navigation_node` headless (`navigation.launch`, 25 Hz, 40 steps a frame) over each "
            "navigation scene's whole procedure, measured from outside on the `stats` topic; "
            "the second table with a subscriber on `xray/image` (512 × 512, 15 frames/s, rendered "
            "on the node's imaging thread).")
    env = read("env_benchmark.txt")
    section("The Python environment", "bash scripts/python.sh scripts/env_benchmark.py",
            "\n".join(l for l in (env or "").splitlines() if l.startswith("|")),
            "\n".join(l[0].upper() + l[1:] + "." for l in (env or "").splitlines() if l.startswith("rollout")),
            "`ArchNavigation-v0` (the wire in the 45° catheter, to the right common carotid) driven "
            "by the same seeded actions for 8 s of simulated time at each control interval and "
            "physics step: one environment in one process, and the native vector environment "
            "with one copy per core; the last column is how far the lead tip ends from the 1 ms "
            "run's after the same actions (median, largest over the actions).")
    g = gbench()
    print("## Parts of the step\n")
    print("Google Benchmark (`test/benchmark/`), one stage alone; CPU time, one core.\n")
    for title, flt, body, what in stages_tables(g):
        section(title, "build/ws/devel/lib/endovascular_sim/evsim_benchmarks --benchmark_min_time=0.2 "
                "--benchmark_filter='%s'" % flt, body, "", what, level=3)
    section("Effects", "/usr/bin/python3 scripts/effects_table.py --scenes carotid,carotid_selective,"
            "carotid_catheter,network,aneurysm,aneurysm_coiling,patient_example", effects_table(), "",
            "Each navigation scene as shipped and with one effect taken out (−) or put in (+): "
            "median / p99 step [ms] over the whole procedure. Empty: the effect cannot be put "
            "in (`vessel_motion` needs motion regions, `coaxial` a device inside another).")
    print("## Accuracy against cost\n")
    section("Contact options", "%s bench accuracy carotid --duration 3 --csv carotid.csv\n"
            "%s bench accuracy aneurysm --duration 0.5 --csv aneurysm.csv\n"
            "%s bench accuracy carotid_catheter --duration 0.5 --csv carotid_catheter.csv\n"
            "/usr/bin/python3 scripts/plot_accuracy.py carotid.csv carotid.png carotid" % (e, e, e),
            *accuracy_table(["carotid", "aneurysm", "carotid_catheter"]),
            "Every key of a scene's `contact:` section (`evsim schema`, as in "
            "[config/scenes/README.md](../config/scenes/README.md)), and what each setting costs and how far it "
            "moves the result. Each scene is run once per setting of one option, the others at the scene's values, "
            "against a fine reference run (a quarter of the time step, twice the elements, wall, "
            "pair and lumen tolerances 1e-8 m, 50 loops, 8 halvings, root tolerance 1e-12 m). "
            "Cost: wall time per simulated second (1 = real time). Tip error: the devices' tips "
            "at the end against the reference's. Deepest: the largest penetration after any "
            "step. Rejected: steps the setting could not solve (tried again without the recovery "
            "options). `carotid_catheter` has friction, so its LCP solver rows are its frictional "
            "solver's.", level=3)
    section("The beam and the root finder alone", "%s bench accuracy beam --csv beam.csv\n"
            "%s bench accuracy root --csv root.csv" % (e, e), alone_tables(), "", "", level=3)
    section("Options over whole procedures", "%s bench FILE   # FILE: the scene with one contact option changed" % e,
            options_whole_table(), "", "The options the sweep above does not vary, each in a copy of "
            "the shipped scene (`build/performance/variants/`), over the whole procedure.", level=3)
    labels = {"predict": "`predict_first_iterate` false", "element_pairs": "`element_pairs` true",
              "pair_tol_5um": "`pair_tolerance` 5 µm", "new_pair_2.5um": "`new_pair_overlap` 2.5 µm",
              "curvature_every_loop": "`curvature_loops` 1000 (every loop)",
              "penetration_5um": "`penetration_tolerance` 5 µm", "sample_point_pairs": "`element_pairs` false",
              "pair_tol_1um": "`pair_tolerance` 1 µm", "new_pair_0": "`new_pair_overlap` 0"}
    for scene, warm, steps, win, ws, where in (
            ("aneurysm", 11400, 600, 24, 10, "where the coil fills the dome"),
            ("aneurysm_packed", 14400, 900, 6, 150, "the dome full")):
        body, what = windows_table("option_windows_%s.txt" % scene, labels)
        section("Options, paired: `%s`" % scene,
                "%s bench %s --warmup %d --steps %d --windows %d --window-steps %d --variant FILE ..."
                % (e, scene, warm, steps, win, ws), body, "",
                "A coil's path is chaotic, so two whole runs differ by chance. Instead the scene "
                "and each variant (the scene with one option changed) are stepped from the same "
                "states of the scene's own run (%s: %s): every variant does the same steps' work. Loops "
                "and rows are counts; deepest is the wall's largest penetration." % (where, what),
                level=3)
    if MISSING:
        print("<!-- not measured: %s -->" % ", ".join(MISSING))


NODE = re.compile(r"^(\S+)\s+([0-9.]+)\s+([0-9.]+)\s+([0-9.]+)\s+([0-9]+)(?:\s+([0-9.]+))?\s*$", re.M)


def node_tables():
    out = []
    for name, xray in (("node_benchmark.txt", False), ("node_benchmark_xray.txt", True)):
        text = read(name)
        if not text:
            continue
        rows = [["`%s`" % m.group(1), m.group(2), m.group(3), m.group(4), m.group(5)] + ([m.group(6)] if xray else [])
                for m in NODE.finditer(text)]
        out.append(table(["scene", "simulated [s]", "RTF held", "frames/s", "longest stall [ms]"]
                         + (["X-ray frames/s"] if xray else []), rows))
    return "\n\n".join(out)


if __name__ == "__main__":
    main(sys.argv)
