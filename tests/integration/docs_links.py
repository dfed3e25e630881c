#!/usr/bin/python3
"""The docs can be followed: every page is reachable, every link lands, every quoted command
names something that exists.

Pages: README.md (the repository root) and every docs/**/*.md (recursively).

This script fails (exit 1, one line per problem) when
  1. a docs page is not reachable from the entries, README.md and docs/README.md (the docs
     index), by following relative links from page to page, transitively;
  2. a relative link of a page points at a file or folder that does not exist, or names an
     anchor (`page.md#anchor`, `#anchor`) that the linked .md page has no heading for
     (GitHub's anchors: lower case, punctuation dropped, spaces to '-', a repeated heading
     gets -1, -2, ...; `<a id="...">` / `<a name="...">` count too). Links are
     `[text](target)` and `![alt](target)` outside code; targets with a scheme (https:,
     mailto:) are not checked;
  3. a command quoted in a page names a repository path that does not exist.

"A command quoted" is any text in code: the lines of a fenced code block (any info string)
and every inline code span (`...`). In it, a repository path is a word that starts, at the
start of the text or after a space, '=', '(', a quote or '|', with one of
    scripts/  tests/  configs/  build/  BUILD/ (= build/, the build folder's placeholder)
optionally preceded by './'. It ends at a space, a quote, a backtick, ')', ',', ';' or ':'
(a trailing '.' is dropped). Such a path must be, with placeholders matched as wildcards:
  - scripts/..., tests/..., configs/...: a file or folder of the source tree; or, for tests/,
    an executable target that tests/ builds (`tests/rve_test_client`); or a Python
    reference `scripts/lib/column_study.run_column` to a function of scripts/lib/column_study.py;
  - build/... : `build/` itself, a folder of it that mirrors a source folder
    (`build/dem_app/`), or an executable that a CMake add_executable() in that folder's
    CMakeLists.txt or its included *.cmake files builds (`build/mpm_app/mpm_app`,
    `build/tests/test_native_restitution` from the tests/unit/test_*.cpp glob).
Placeholders (each matches any name in its place): an upper-case word of two or more letters
(RUN_DIR, SCENE, STUDY), <...>, ${...}, $NAME, '*', '...', a brace list {a,b} (every
alternative must exist), and a one-letter file stem (configs/x.yaml, configs/a.yaml: an
example name). So a renamed or deleted script, scene, test or executable fails, and a
placeholder does not.

In addition, in fenced blocks marked `sh`, the program of every command line (its first word
after VAR=value assignments; not a continuation line, a comment or a shell keyword) must be a
repository path as above, an executable target of the build (`mpm_app`, `dem_app`,
`element_test`, ...) or one of the external programs listed in EXTERNAL.

It then checks itself: a planted broken link, a planted anchor that no heading has, a planted
unreachable page and a planted nonexistent script must each be reported.

Usage: docs_links.py SOURCE_DIR
"""
import glob
import os
import re
import sys
from pathlib import Path

ROOTS = ("scripts", "tests", "configs", "build")
EXTERNAL = {
    "cmake", "ctest", "make", "mpirun", "mpiexec", "ompi-server", "srun", "sbatch", "salloc",
    "python3", "/usr/bin/python3", "bash", "sh", "env", "time", "sudo", "apt-get", "git", "ip",
    "printf", "echo", "sed", "grep", "cat", "ls", "cd", "export", "cp", "mv", "rm", "mkdir",
    "tar", "diff", "jq", "ssh", "nohup", "kill", "wait", "yade", "gdb", "valgrind", "perf",
    "nvidia-smi", "taskset", "unshare", "exec", "numactl", "head", "tail", "watch", "pip", "du", "find", "test",
}
SHELL_WORDS = {"for", "do", "done", "if", "then", "else", "elif", "fi", "while", "case", "esac",
               "}", "{", "(", ")", "&&", "||", "|"}

FENCE = re.compile(r"^([ \t]*)(```+|~~~+)([^\n]*)\n(.*?)^\1\2[ \t]*$", re.S | re.M)
INLINE = re.compile(r"(`+)(.+?)\1", re.S)
LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*<?([^)\s>]*)>?(?:\s+\"[^\"]*\")?\s*\)")
HEADING = re.compile(r"^ {0,3}(#{1,6})\s+(.*?)\s*#*\s*$", re.M)
HTML_ANCHOR = re.compile(r"<a\s+(?:id|name)=\"([^\"]+)\"", re.I)
PATH_WORD = re.compile(
    r"(?:^|(?<=[\s=(\"'|\[]))(?:\./)?((?:scripts|tests|configs|build|BUILD)/"
    r"(?:\{[^{}\s]*\}|[^\s\"'`),;:{])*)")
PLACEHOLDER = re.compile(r"<[^>/]*>|\$\{[^}]*\}|\$[A-Za-z_]\w*|\.\.\.|…|\b[A-Z][A-Z0-9_]+\b")


def slug(heading: str) -> str:
    """GitHub's anchor for a heading's text."""
    s = re.sub(r"<[^>]+>", "", heading)
    s = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", s)  # a link in a heading: its text
    s = s.strip().lower()
    s = re.sub(r"[^\w\- ]", "", s)
    return s.replace(" ", "-")


def strip_code(text: str) -> str:
    """The text with fenced blocks and inline code blanked (line numbers kept)."""
    text = FENCE.sub(lambda m: "\n" * m.group(0).count("\n"), text)
    return INLINE.sub(lambda m: " " * len(m.group(0)), text)


def code_texts(text: str) -> list:
    """[(line, info string or None for inline code, text)] of a page's code."""
    out = []
    for m in FENCE.finditer(text):
        out.append((text.count("\n", 0, m.start()) + 2, m.group(3).strip(), m.group(4)))
    rest = FENCE.sub(lambda m: "\n" * m.group(0).count("\n"), text)
    for m in INLINE.finditer(rest):
        out.append((rest.count("\n", 0, m.start()) + 1, None, m.group(2)))
    return out


def anchors_of(text: str) -> set:
    found, seen = set(), {}
    for m in HEADING.finditer(strip_code_fences(text)):
        a = slug(m.group(2))
        n = seen.get(a, 0)
        seen[a] = n + 1
        found.add(a if n == 0 else f"{a}-{n}")
    found.update(HTML_ANCHOR.findall(text))
    return found


def strip_code_fences(text: str) -> str:
    return FENCE.sub(lambda m: "\n" * m.group(0).count("\n"), text)


class Tree:
    """What exists: the source tree's files and the CMake executables, by build folder."""

    def __init__(self, root: Path):
        self.root = root
        self.targets = {}  # build folder relative to build/ ('' for the top) -> {names}
        for cm in list(root.glob("CMakeLists.txt")) + [
                p for d in ("interface", "laws", "mpm_app", "dem_app", "tests")
                for p in (root / d).rglob("*") if p.name == "CMakeLists.txt"
                or p.suffix == ".cmake"]:
            folder = self.build_folder(cm)
            text = cm.read_text(encoding="utf-8", errors="replace")
            names = self.targets.setdefault(folder, set())
            for name in re.findall(r"add_executable\(\s*([A-Za-z0-9_.+-]+)", text):
                names.add(name)
            if "add_executable(${name}" in text:  # the unit-test glob: tests/unit/test_*.cpp
                m = re.search(r"GLOB\s+\w+\s+(?:CONFIGURE_DEPENDS\s+)?\$\{CMAKE_CURRENT_SOURCE_DIR\}/"
                              r"(\S+)\)", text)
                if m:
                    for src in (cm.parent).glob(m.group(1)):
                        names.add(src.stem)

    def build_folder(self, cmake_file: Path) -> str:
        """The build folder a CMake file's targets land in: the folder of the CMakeLists.txt
        that includes it (tests/integration/*.cmake are included by tests/CMakeLists.txt)."""
        d = cmake_file.parent
        while d != self.root and not (d / "CMakeLists.txt").is_file():
            d = d.parent
        return "" if d == self.root else d.relative_to(self.root).as_posix()

    def executables(self) -> set:
        return {n for names in self.targets.values() for n in names}

    def source_matches(self, pattern: str) -> bool:
        pattern = pattern.rstrip("/")
        if not any(ch in pattern for ch in "*?["):
            return (self.root / pattern).exists()
        return bool(glob.glob(str(self.root / pattern)))


def expand_braces(path: str) -> list:
    m = re.search(r"\{([^{}$]*,[^{}]*)\}", path)
    if not m:
        return [path]
    return [q for alt in m.group(1).split(",")
            for q in expand_braces(path[:m.start()] + alt + path[m.end():])]


def to_glob(path: str) -> str:
    path = PLACEHOLDER.sub("*", path)
    # a one-letter file stem is an example name: configs/x.yaml
    path = re.sub(r"(?<=/)[a-z](?=\.[A-Za-z0-9]+$)", "*", path)
    return re.sub(r"\*+", "*", path)


def path_exists(tree: Tree, word: str) -> bool:
    word = word.rstrip(".")
    if word.startswith("BUILD/"):
        word = "build/" + word[len("BUILD/"):]
    for alt in expand_braces(word):
        if not one_path_exists(tree, alt):
            return False
    return True


def one_path_exists(tree: Tree, word: str) -> bool:
    pattern = to_glob(word)
    top, _, rest = pattern.partition("/")
    if top == "build":
        rest = rest.rstrip("/")
        if not rest:
            return True
        folder, _, name = rest.rpartition("/")
        if (tree.root / rest).is_dir():
            return True  # a build folder that mirrors a source folder
        names = tree.targets.get(folder, set())
        return any(glob.fnmatch.fnmatchcase(n, name) for n in names)
    if tree.source_matches(pattern):
        return True
    if top == "tests" and "/" not in rest:
        if any(glob.fnmatch.fnmatchcase(n, rest) for n in tree.targets.get("tests", set())):
            return True
    m = re.fullmatch(r"(.+)\.([A-Za-z_]\w*)", pattern)  # a Python reference: module.function
    if m and tree.source_matches(m.group(1) + ".py"):
        return True
    return False


def command_programs(block: str) -> list:
    """[(offset line, program)] of the command lines of an sh block."""
    out, continued = [], False
    for i, line in enumerate(block.splitlines()):
        s = line.strip()
        was_continued, continued = continued, s.endswith("\\")
        if was_continued or not s or s.startswith("#"):
            continue
        s = re.sub(r"^\$\s+", "", s)
        s = re.sub(r"\$\(\(.*?\)\)|'[^']*'|\"[^\"]*\"", "Q", s)  # quoted text, arithmetic
        s = re.sub(r"(^|\s)#.*", "", s)  # a comment
        for part in re.split(r"\s*(?:&&|\|\||;|\|)\s*", s):
            words = part.split()
            while words and re.fullmatch(r"[A-Za-z_]\w*=\S*", words[0]):
                words.pop(0)
            if words and words[0] in ("time", "sudo", "env", "nohup"):
                words.pop(0)
            if not words or words[0] in SHELL_WORDS or words[0] == "\\" or words[0].startswith(("-", "[", "#", "$(")):
                continue
            out.append((i, words[0]))
            if words[0] in ("for", "while", "if"):
                break
    return out


COUNTS = {"links": 0, "paths": 0, "programs": 0}


def check(pages: dict, tree: Tree) -> list:
    errors = []
    counts = {"links": 0, "paths": 0, "programs": 0}
    anchors = {name: anchors_of(text) for name, text in pages.items()}
    graph = {}
    for name, text in sorted(pages.items()):
        graph[name] = set()
        prose = strip_code(text)
        for m in LINK.finditer(prose):
            target = m.group(1)
            where = f"{name}:{prose.count(chr(10), 0, m.start()) + 1}"
            if not target or re.match(r"[A-Za-z][\w+.-]*:", target):
                continue
            counts["links"] += 1
            path, _, anchor = target.partition("#")
            resolved = (os.path.normpath(os.path.join(os.path.dirname(name), path))
                        if path else name)
            if path and not (tree.root / resolved).exists() and resolved not in pages:
                errors.append(f"{where}: links {target}: {resolved} does not exist")
                continue
            if resolved.endswith(".md"):
                graph[name].add(resolved)
                if anchor and resolved in anchors and anchor not in anchors[resolved]:
                    errors.append(f"{where}: links {target}: {resolved} has no heading "
                                  f"for #{anchor}")
        for line, info, code in code_texts(text):
            for m in PATH_WORD.finditer(code):
                word = m.group(1).rstrip(".")
                counts["paths"] += 1
                if word in ("build", "BUILD") or not path_exists(tree, word):
                    if word in ("build/", "BUILD/"):
                        continue
                    at = line + (code.count("\n", 0, m.start()) if info is not None else 0)
                    errors.append(f"{name}:{at}: `{word}` names no file, folder or CMake "
                                  f"target of the repository")
            if info in ("sh", "bash", "shell", "console"):
                known = EXTERNAL | tree.executables()
                for i, prog in command_programs(code):
                    counts["programs"] += 1
                    if prog.startswith(tuple(r + "/" for r in ROOTS + ("BUILD",))):
                        continue  # checked as a path above
                    if prog not in known:
                        errors.append(f"{name}:{line + i}: the command `{prog}` is neither a "
                                      f"repository path, a CMake executable nor a known "
                                      f"program (EXTERNAL in {Path(__file__).name})")
    # Reachability from the entries.
    entries = [p for p in ("README.md", "docs/README.md") if p in pages]
    if "docs/README.md" not in pages:
        errors.append("docs/README.md (the docs index) is missing")
    seen, todo = set(entries), list(entries)
    while todo:
        for target in graph.get(todo.pop(), ()):
            if target in pages and target not in seen:
                seen.add(target)
                todo.append(target)
    for name in sorted(pages):
        if name.startswith("docs/") and name not in seen:
            errors.append(f"{name} is not reachable by links from README.md or docs/README.md")
    COUNTS.update(counts)
    return errors


def load(root: Path) -> dict:
    pages = {"README.md": (root / "README.md").read_text(encoding="utf-8")}
    for p in sorted((root / "docs").rglob("*.md")):
        pages[p.relative_to(root).as_posix()] = p.read_text(encoding="utf-8")
    return pages


def self_check(pages: dict, tree: Tree) -> list:
    """Each planted fault must be reported."""
    index = pages["docs/README.md"]
    plants = {
        "a broken link": ({"docs/README.md": index + "\n[x](no_such_page.md)\n"},
                          "no_such_page.md"),
        "a missing anchor": ({"docs/README.md": index + "\n[x](results.md#no-such-heading)\n"},
                             "#no-such-heading"),
        "an unreachable page": ({"docs/orphan_page.md": "# Orphan\n"}, "orphan_page.md"),
        "a nonexistent script": ({"docs/README.md": index + "\n`scripts/no_such_script --x`\n"},
                                 "scripts/no_such_script"),
        "a nonexistent executable": (
            {"docs/README.md": index + "\n```sh\nno_such_program --x\n```\n"}, "no_such_program"),
    }
    problems = []
    for what, (change, needle) in plants.items():
        if not any(needle in e for e in check({**pages, **change}, tree)):
            problems.append(f"self-check: {what} ({needle}) was not reported")
    return problems


def main() -> int:
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    root = Path(sys.argv[1]).resolve()
    tree = Tree(root)
    pages = load(root)
    errors = check(pages, tree)
    for e in errors:
        print(f"docs_links: {e}")
    if errors:
        print(f"docs_links: FAILED ({len(errors)} problems)")
        return 1
    problems = self_check(pages, tree)
    for p in problems:
        print(f"docs_links: {p}")
    if problems:
        return 1
    check(pages, tree)  # the counts of the real pages (the self-check overwrote them)
    print(f"docs_links: ok: {len(pages)} pages, all reachable from README.md and "
          f"docs/README.md; {COUNTS['links']} relative links land; {COUNTS['paths']} quoted "
          f"repository paths and {COUNTS['programs']} commands' programs exist")
    return 0


if __name__ == "__main__":
    sys.exit(main())
