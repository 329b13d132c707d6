#!/usr/bin/env python3
"""The documentation's commands and links, checked so that they cannot rot.

Every fenced ```bash block that follows a line `<!-- runnable -->` in
README.md, docs/*.md and config/*/README.md is run as one bash script from
the repository root (`set -euo pipefail`; `$evsim` preset to the built
evsim), and must exit 0 within its time limit (`<!-- runnable timeout=S
-->`, default 300 s). Every relative Markdown link must name a file that
exists. Writes one JUnit case per block and per page (catkin's test results),
and exits 1 when any fails.

usage: doc_commands_test.py REPO EVSIM [XML]   (XML: the JUnit file to write)
"""
import glob
import os
import re
import subprocess
import sys
import time
import xml.etree.ElementTree as ET

BLOCK = re.compile(r"^<!-- runnable(?: timeout=(\d+))? -->\n```bash\n(.*?)^```", re.M | re.S)
LINK = re.compile(r"\]\(([^)#\s]+)(?:#[^)]*)?\)")


def pages(repo):
    found = [os.path.join(repo, "README.md")]
    found += sorted(glob.glob(os.path.join(repo, "docs", "*.md")))
    found += sorted(glob.glob(os.path.join(repo, "config", "*", "README.md")))
    return found


def run_block(repo, evsim, script, timeout):
    env = dict(os.environ, evsim=evsim, PATH="/usr/bin:" + os.environ.get("PATH", ""))
    try:
        out = subprocess.run(["bash", "-c", "set -euo pipefail\n" + script], cwd=repo, env=env,
                             capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return "over its time limit of %d s" % timeout
    if out.returncode != 0:
        tail = (out.stderr or out.stdout).strip().splitlines()[-5:]
        return "exit %d:\n%s" % (out.returncode, "\n".join(tail))
    return ""


def main(argv):
    # The repository itself, where the docs' relative paths (build/ws/...)
    # start: the catkin package links each of its entries to it.
    repo = os.path.dirname(os.path.realpath(os.path.join(argv[1], "README.md")))
    evsim = os.path.abspath(argv[2])
    xml_path = argv[3] if len(argv) > 3 else None  # (positional: catkin's wrapper owns --options)
    cases = []  # (name, seconds, failure or "")
    for page in pages(repo):
        text = open(page, encoding="utf-8").read()
        rel = os.path.relpath(page, repo)
        broken = [t for t in LINK.findall(text) if not re.match(r"[a-z]+:", t)
                  and not os.path.exists(os.path.join(os.path.dirname(page), t))]
        cases.append(("links " + rel, 0.0, "broken links: " + ", ".join(broken) if broken else ""))
        for m in BLOCK.finditer(text):
            line = text.count("\n", 0, m.start()) + 2
            start = time.time()
            why = run_block(repo, evsim, m.group(2), int(m.group(1) or 300))
            cases.append(("commands %s:%d" % (rel, line), time.time() - start, why))
    failed = [c for c in cases if c[2]]
    for name, seconds, why in cases:
        print("%-6s %s (%.1f s)%s" % ("FAILED" if why else "ok", name, seconds,
                                      "\n  " + why.replace("\n", "\n  ") if why else ""))
    blocks = sum(1 for c in cases if c[0].startswith("commands"))
    print("%d pages, %d runnable blocks, %d failed" % (len(pages(repo)), blocks, len(failed)))
    if xml_path:
        suite = ET.Element("testsuite", name="doc_commands", tests=str(len(cases)),
                           failures=str(len(failed)), errors="0")
        for name, seconds, why in cases:
            case = ET.SubElement(suite, "testcase", classname="docs", name=name,
                                 time="%.3f" % seconds)
            if why:
                ET.SubElement(case, "failure", message=why.splitlines()[0]).text = why
        os.makedirs(os.path.dirname(xml_path), exist_ok=True)
        ET.ElementTree(suite).write(xml_path, encoding="utf-8", xml_declaration=True)
    return 1 if failed or blocks == 0 else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
