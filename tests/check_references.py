#!/usr/bin/python3
"""Dangling references in the documentation and in the comments of the code.

Usage: /usr/bin/python3 tests/check_references.py   (from anywhere; checks the repository)
Prints one line FILE:LINE: PROBLEM per problem; exit 0 when clean, 1 otherwise.

Scanned: README.md and docs/*.md (whole text), and the comments and docstrings of the
code: edp/**/*.edp, *.idp, *.cpp, *.hpp, *.awk, *.txt, *.scene, *.py; tests/*.sh, *.py, *.edp;
plots/*.py; run.sh; meshes/*.geo; .ci/run. Rules:

1. Paths. Every token that starts with edp/, tests/, plots/, docs/ or meshes/, and every
   run.sh or .ci/run, must exist (from the repository root). Upper-case words and <words>
   are placeholders (tests/ref/CASE/, meshes/<geometry>.geo), so they and * match any name.
   Ignored: the folders made at run time, listed in RUNTIME below.
2. Markdown links [text](target) in README.md and docs/*.md: a relative target must exist
   (relative to the file that links); #anchor must be the GitHub slug of a heading of the
   target (or of the same file).
3. Citations of a section, in these forms only:
       README "Heading"      README section "Heading"      README, "Heading"
       docs/NAME.md, section "Heading"      docs/NAME.md, "Heading"
       "Heading" in the README             "Heading" in docs/NAME.md
   The cited file must exist and have a heading with that text (any level).
4. Nothing may point at the original design notes or the tracker: no mention of the
   shared folder above the repository, of the upper-case design file, or of an issue
   number ("issue 4", "issue #5"). These are checked in the whole text of every file.
This file itself is not scanned: its docstring shows the forms it looks for.
"""
import glob
import io
import os
import re
import sys
import tokenize

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RUNTIME = ("tests/work/", "meshes/build/", "edp/plugins/build/")  # made by runs, not in git
SELF = "tests/check_references.py"
CODE = ["edp/**/*.edp", "edp/**/*.idp", "edp/**/*.cpp", "edp/**/*.hpp", "edp/**/*.awk",
        "edp/**/*.txt", "edp/**/*.scene", "edp/**/*.py", "tests/*.sh", "tests/*.py", "tests/*.edp",
        "plots/*.py", "run.sh", "meshes/*.geo", ".ci/run"]
DOCS = ["README.md", "docs/*.md"]

PATH = re.compile(r"(?<![\w./$~-])(?:\./)?((?:edp|tests|plots|docs|meshes)/[\w.*<>/-]*|run\.sh\b|\.ci/run\b)")
LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")
FILE = r"(README(?:\.md)?|docs/[\w-]+\.md)"
CITATION = re.compile(FILE + r"(?:'s)?,?\s+(?:sections?\s+)?\"([^\"]+)\"|\"([^\"]+)\"\s+in\s+(?:the\s+)?" + FILE)
FORBIDDEN = re.compile(r"\.\./shared|/work/shared|DESIGN\.md|\b[Ii]ssues?\s+#?\d+")


def comment_text(path, text):
    """The comments (and Python docstrings) of a code file, line for line: other text blanked."""
    lines = text.split("\n")
    kept = [""] * len(lines)
    if path.endswith(".py"):
        try:
            for tok in tokenize.generate_tokens(io.StringIO(text).readline):
                if tok.type == tokenize.COMMENT or (tok.type == tokenize.STRING and re.match(r"[rRbBuU]*(\"\"\"|''')", tok.string)):
                    for i, part in enumerate(tok.string.split("\n")):
                        kept[tok.start[0] - 1 + i] += " " + part
        except (tokenize.TokenError, IndentationError, SyntaxError):
            pass
        return "\n".join(kept)
    slashes = path.endswith((".edp", ".idp", ".cpp", ".hpp", ".geo"))
    in_block = False
    for n, line in enumerate(lines):
        quote, i = None, 0
        while i < len(line):
            c = line[i]
            if in_block:
                end = line.find("*/", i)
                kept[n] += " " + line[i:] if end < 0 else " " + line[i:end]
                if end < 0:
                    break
                in_block, i = False, end + 2
                continue
            if quote:
                quote = None if c == quote else quote
                i += 2 if c == "\\" else 1
                continue
            if c in "\"'" and not (c == "'" and slashes):
                quote = c
            elif slashes and line.startswith("//", i):
                kept[n] += " " + line[i + 2:]
                break
            elif slashes and line.startswith("/*", i):
                in_block, i = True, i + 2
                continue
            elif not slashes and c == "#" and (i == 0 or line[i - 1] in " \t") and not line.startswith("#!", i):
                kept[n] += " " + line[i + 1:]
                break
            i += 1
    return "\n".join(kept)


def without_fences(text):
    """Markdown text with the fenced code blocks blanked (line numbers kept)."""
    out, fenced = [], False
    for line in text.split("\n"):
        if line.lstrip().startswith("```"):
            fenced = not fenced
            out.append("")
        else:
            out.append("" if fenced else line)
    return "\n".join(out)


def headings(path):
    """Heading texts of a markdown file (backticks and emphasis removed)."""
    with open(path, encoding="utf-8") as f:
        text = without_fences(f.read())
    return [re.sub(r"[`*]", "", m.group(1)).strip() for m in re.finditer(r"^#{1,6}\s+(.+?)\s*#*\s*$", text, re.M)]


def slugs(path):
    """GitHub anchors of the headings of a markdown file (repeats get -1, -2, ...)."""
    seen, out = {}, set()
    for h in headings(path):
        s = "".join(c for c in h.lower() if c.isalnum() or c in " _-").replace(" ", "-")
        out.add(s if s not in seen else f"{s}-{seen[s]}")
        seen[s] = seen.get(s, 0) + 1
    return out


def path_exists(token):
    token = token.rstrip(".,:;-")
    if token.startswith(RUNTIME) or token + "/" in RUNTIME:
        return True
    pattern = re.sub(r"<[^>]*>", "*", token)
    pattern = "/".join(re.sub(r"(?<![a-z])[A-Z][A-Z0-9_]*(?![a-z])", "*", part) for part in pattern.split("/"))
    full = os.path.normpath(os.path.join(ROOT, pattern))
    return bool(glob.glob(full)) if "*" in pattern else os.path.exists(full)


def check(rel, text, scanned, markdown):
    """Problems of one file: text is the whole file, scanned the part searched for paths."""
    problems = []
    line_of = lambda t, pos: t.count("\n", 0, pos) + 1
    for m in FORBIDDEN.finditer(text):
        problems.append((line_of(text, m.start()), f"mentions '{m.group(0)}' (the repository must stand alone)"))
    for m in PATH.finditer(scanned):
        if not path_exists(m.group(1)):
            problems.append((line_of(scanned, m.start()), f"no such path: {m.group(1).rstrip('.,:;-')}"))
    prose = without_fences(text) if markdown else scanned
    if markdown:
        for m in LINK.finditer(prose):
            target = m.group(1)
            if re.match(r"[a-z]+:", target):
                continue
            file_part, _, anchor = target.partition("#")
            dest = os.path.normpath(os.path.join(ROOT, os.path.dirname(rel), file_part)) if file_part else os.path.join(ROOT, rel)
            if not os.path.exists(dest):
                problems.append((line_of(prose, m.start()), f"link to a missing file: {target}"))
            elif anchor and (not dest.endswith(".md") or anchor not in slugs(dest)):
                problems.append((line_of(prose, m.start()), f"link to a missing heading: {target}"))
    for m in CITATION.finditer(prose):
        name, section = (m.group(1), m.group(2)) if m.group(1) else (m.group(4), m.group(3))
        name = "README.md" if name.startswith("README") else name
        section = " ".join(section.split())
        target = os.path.join(ROOT, name)
        if not os.path.exists(target):
            problems.append((line_of(prose, m.start()), f"cites a missing file: {name}"))
        elif section.lower() not in (h.lower() for h in headings(target)):
            problems.append((line_of(prose, m.start()), f'cites {name}, "{section}": no such heading'))
    return [f"{rel}:{n}: {p}" for n, p in sorted(problems)]


def main():
    os.chdir(ROOT)
    problems = []
    for markdown, patterns in ((True, DOCS), (False, CODE)):
        files = sorted({f for p in patterns for f in glob.glob(p, recursive=True)})
        for rel in files:
            if rel == SELF or rel.startswith(RUNTIME):
                continue
            with open(rel, encoding="utf-8", errors="replace") as f:
                text = f.read()
            problems += check(rel, text, text if markdown else comment_text(rel, text), markdown)
    for line in problems:
        print(line)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
