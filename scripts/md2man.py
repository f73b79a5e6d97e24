#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-2.0
"""Markdown, as the project's documents write it, to man page sections, so
that a page says what its document says (scripts/mkman.sh):

    md2man.py FILE                 the whole document: "## X" becomes .SH X
    md2man.py FILE HEADING         only the part under "## HEADING" (its body)

The subset: ## and ### headings, paragraphs, "- " lists, indented code
blocks, tables (a row each: the first cell as the tag, the others with
their column names), `code`, **bold**, [links](target) (their text). The
"# title" is left out (the page has its own NAME); what follows it, up
to the first "## ", is the DESCRIPTION.
"""
import re
import sys


# Characters of the documents that roff spells by name.
NAMED = {"²": "^2", "³": "^3", "≠": "\\(!=", "≥": "\\(>=", "≤": "\\(<=", "−": "\\-",
         "×": "\\(mu", "—": "\\(em", "–": "\\(en", "→": "\\(->", "µ": "u", "°": "\\(de",
         "±": "\\(+-", "⁶": "^6", "…": "...", "’": "'", "“": "\\(lq", "”": "\\(rq"}


def inline(text):
    """Text to roff: escapes, then code and bold in bold, links as their text."""
    text = text.replace("\\", "\\e").replace("-", "\\-")
    text = "".join(NAMED.get(c, c) for c in text)
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", text)
    text = re.sub(r"\*\*([^*]+)\*\*", r"\\fB\1\\fR", text)
    text = re.sub(r"`([^`]+)`", r"\\fB\1\\fR", text)
    return text


def line_out(text):
    """A text line that roff must not take for a request."""
    return "\\&" + text if text[:1] in (".", "'") else text


def cells(row):
    return [c.strip() for c in row.strip().strip("|").split("|")]


def convert(lines):
    out = []
    i = 0
    while i < len(lines):
        line = lines[i]
        if line.startswith("# "):
            i += 1
        elif line.startswith("## "):
            out.append(".SH " + inline(line[3:].strip()).upper())
            i += 1
        elif line.startswith("### "):
            out.append(".SS " + inline(line[4:].strip()))
            i += 1
        elif not line.strip():
            i += 1
        elif line.startswith("    "):
            out += [".PP", ".RS 4", ".nf"]
            while i < len(lines) and (lines[i].startswith("    ") or not lines[i].strip()):
                if lines[i].strip() or (i + 1 < len(lines) and lines[i + 1].startswith("    ")):
                    out.append(line_out(lines[i][4:].replace("\\", "\\e").replace("-", "\\-")))
                i += 1
            out += [".fi", ".RE"]
        elif line.startswith("|"):
            head = cells(line)
            i += 2  # the header and its |---| line
            while i < len(lines) and lines[i].startswith("|"):
                row = cells(lines[i])
                out += [".TP", ".B " + inline(row[0].replace("`", ""))]
                rest = row[1:]
                if len(rest) == 1:
                    out.append(line_out(inline(rest[0])))
                else:
                    for name, value in zip(head[1:], rest):
                        text = inline(value) if name in ("meaning", "what") else inline(name) + ": " + inline(value)
                        out += [line_out(text), ".br"]
                    out.pop()
                i += 1
        elif line.startswith("- "):
            item = [line[2:].strip()]
            i += 1
            while i < len(lines) and lines[i].startswith("  ") and lines[i].strip():
                item.append(lines[i].strip())
                i += 1
            out += [".IP \\(bu 2", line_out(inline(" ".join(item)))]
        else:
            para = []
            while i < len(lines) and lines[i].strip() and not re.match(r"(#|- |\||    )", lines[i]):
                para.append(lines[i].strip())
                i += 1
            out += [".PP", line_out(inline(" ".join(para)))]
    return out


def main():
    lines = open(sys.argv[1], encoding="utf-8").read().split("\n")
    if len(sys.argv) > 2:
        start = lines.index("## " + sys.argv[2]) + 1
        end = next((k for k in range(start, len(lines)) if lines[k].startswith("## ")), len(lines))
        lines = lines[start:end]
    else:  # what comes before the first "## " describes the whole
        lines = [k for k in lines if not k.startswith("# ")]
        lines.insert(0, "## Description")
    print("\n".join(convert(lines)))


main()
