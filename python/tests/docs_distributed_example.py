"""Runs the "Try it on one machine" block of docs/distributed.md as printed (scripts/python-ci.sh
runs it in a fresh venv with the wheel's [distributed] extra). Not a pytest module."""

import sys

if __name__ == "__main__":  # worker processes re-import this file: only the parent runs it
    text = open(sys.argv[1]).read()
    section = text.split("## Try it on one machine", 1)[1]
    block = section.split("```python\n", 1)[1].split("```", 1)[0]
    exec(compile(block, "docs/distributed.md", "exec"), {"__name__": "__main__"})
