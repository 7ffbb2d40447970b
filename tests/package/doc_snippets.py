#!/usr/bin/env python3
"""Writes docs/cpp.md's ```cpp blocks as one program, so that the package test compiles and runs
them against the staged install: the page's snippets stay true.

Usage: doc_snippets.py DOCS_CPP_MD OUT_CPP

The page's convention: the blocks are consecutive steps of one main(); a block's #include lines
go to the top of the file and its `namespace x = …;` lines before main().
"""
import pathlib
import re
import sys

page, out = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])
blocks = re.findall(r"^```cpp\n(.*?)^```", page.read_text(), flags=re.S | re.M)
if not blocks:
    sys.exit(f"doc_snippets.py: {page} has no cpp block")
includes, aliases, body = [], [], []
for block in blocks:
    for line in block.splitlines():
        if line.startswith("#include"):
            includes.append(line)
        elif line.startswith("namespace "):
            aliases.append(line)
        else:
            body.append("  " + line if line else "")
includes = sorted(set(includes)) + ["#include <memory>"]
out.write_text("// Generated from %s by tests/package/doc_snippets.py.\n" % page.name +
               "\n".join(includes) + "\n\n" + "\n".join(aliases) +
               "\n\nint main() {\n" + "\n".join(body) + "\n  return 0;\n}\n")
