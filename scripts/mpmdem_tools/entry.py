"""What the thin entries in scripts/ share: --help from the script's own header comment, and
the `--option value` loop the bash scripts had, with their messages and exit codes."""
from __future__ import annotations

import sys
from pathlib import Path


def header_help(script: str | Path) -> str:
    """The comment block after line 1 of a script, '# ' stripped (as the scripts' --help)."""
    lines = []
    for i, line in enumerate(Path(script).read_text().splitlines()):
        if i == 0:
            continue
        if not line.startswith("#"):
            break
        lines.append(line[2:] if line.startswith("# ") else line[1:])
    return "\n".join(lines)


def parse_options(argv: list[str], tool: str, script: str | Path, options: dict,
                  repeatable: tuple = ()) -> dict:
    """`--name value` pairs into a dict keyed by option name (without dashes); options maps
    name -> default; names in `repeatable` collect a list. -h/--help prints the header and
    exits 0; an unknown argument exits 2 with "TOOL: unknown argument 'X' (see --help)"; a
    missing value exits 2 naming the option."""
    values = {k: (list(v) if k in repeatable else v) for k, v in options.items()}
    i = 0
    while i < len(argv):
        a = argv[i]
        if a in ("-h", "--help"):
            try:
                print(header_help(script))
            except BrokenPipeError:  # e.g. --help | head
                pass
            sys.exit(0)
        name = a[2:] if a.startswith("--") else None
        if name not in options:
            print(f"{tool}: unknown argument '{a}' (see --help)", file=sys.stderr)
            sys.exit(2)
        if i + 1 >= len(argv):
            print(f"{tool}: {a} needs a value (see --help)", file=sys.stderr)
            sys.exit(2)
        if name in repeatable:
            values[name].append(argv[i + 1])
        else:
            values[name] = argv[i + 1]
        i += 2
    return values


def fail(tool: str, message: str, code: int = 2):
    """Print 'TOOL: message' to stderr and exit with `code`."""
    print(f"{tool}: {message}", file=sys.stderr)
    sys.exit(code)
