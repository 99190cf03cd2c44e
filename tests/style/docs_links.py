#!/usr/bin/env python3
"""docs_links.py ROOT DEMSA: the docs a reader follows hold. Prints every fault and exits 1 when there is one:
- every `demsa SUBCOMMAND` in the code of README.md, docs/tutorials/, docs/how-to/ and
  docs/reference/command-line.md (fenced blocks and inline code) is a
  command: `DEMSA SUBCOMMAND --help` exits 0 and prints that command's usage;
- every examples/... path they name exists (a path without an extension may be the folder a study file of that
  name writes, or a file in it: examples/calibration/pile/ for examples/calibration/pile.toml);
- every relative link or image of README.md, CONTRIBUTING.md, ARCHITECTURE.md and docs/**/*.md resolves.
Used by tests/style/docs_links.test.sh."""
import pathlib
import re
import subprocess
import sys

root = pathlib.Path(sys.argv[1])
demsa = sys.argv[2]
faults = []


def code_of(text):
    """The code of a markdown text: fenced blocks and inline spans, with their line numbers."""
    out, fenced = [], False
    for number, line in enumerate(text.splitlines(), 1):
        if line.lstrip().startswith("```"):
            fenced = not fenced
            continue
        if fenced:
            out.append((number, line))
        else:
            out.extend((number, span) for span in re.findall(r"`([^`]+)`", line))
    return out


checked = {}
for page in [root / "README.md", *sorted((root / "docs" / "tutorials").glob("*.md")),
             *sorted((root / "docs" / "how-to").glob("*.md")), root / "docs" / "reference" / "command-line.md"]:
    name = page.relative_to(root)
    text = page.read_text()
    for number, code in code_of(text):
        for command in re.findall(r"(?:^|[\s/(])demsa ([a-z][a-z-]*)\b", code):
            if command not in checked:
                run = subprocess.run([demsa, command, "--help"], capture_output=True, text=True)
                # An unknown word prints demsa's own help with status 0: the command's help names it.
                checked[command] = run.returncode == 0 and f"Usage: demsa {command} " in run.stdout
            if not checked[command]:
                faults.append(f"{name}:{number}: demsa {command}: no such command (--help fails)")
    for number, line in enumerate(text.splitlines(), 1):
        for path in re.findall(r"(?<![\w/.])(examples/[A-Za-z0-9_./-]*[A-Za-z0-9_/-])", line):
            target = root / path
            if target.exists():
                continue
            parts = path.rstrip("/").split("/")
            if any((root / ("/".join(parts[:i]) + ".toml")).exists() for i in range(2, len(parts) + 1)):
                continue  # a study folder that a study file of that name writes, or a file in it
            faults.append(f"{name}:{number}: {path}: no such file")

pages = [root / "README.md", root / "CONTRIBUTING.md", root / "ARCHITECTURE.md", *sorted((root / "docs").rglob("*.md"))]
for page in pages:
    name = page.relative_to(root)
    fenced = False
    for number, line in enumerate(page.read_text().splitlines(), 1):
        if line.lstrip().startswith("```"):
            fenced = not fenced
        if fenced:
            continue
        for link in re.findall(r"\]\(([^)\s]+)\)", line):
            if re.match(r"^[a-z]+:", link) or link.startswith("#"):
                continue
            target = (page.parent / link.split("#")[0]).resolve()
            if not target.exists():
                faults.append(f"{name}:{number}: link {link}: {target} does not exist")

for fault in faults:
    print(fault)
print(f"{len(checked)} commands, {len(pages)} pages checked; {len(faults)} faults")
sys.exit(1 if faults else 0)
