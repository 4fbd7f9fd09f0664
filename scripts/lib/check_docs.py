#!/usr/bin/env python3
"""Every script, option, experiment and file the docs name exists (issue 45 item 7; scripts/lint):
  check_docs.py            every Markdown file git knows (docs/, README.md, the other READMEs)
  check_docs.py FILE...    those files, the names in them looked up in this workspace
Prints `FILE:LINE: what is missing` for each finding and exits 1; exits 0 when every name exists
(printing `N files, every name exists`); 2 on bad input (a FILE that cannot be read).

What counts as naming something. Code is a fenced block, one command a line (with `\\`
continuations), or an inline `span`, which may run over lines of its paragraph; prose is the rest.
- A file: a path starting docs/, src/, config/, launch/, scripts/ or rosbags/, in code or prose,
  not straight after a letter, digit, `/`, `.`, `$` or `-` (so not a URL, $PWD/config/... or
  DIR/config/...), exists from the workspace root; a src/ path also counts when it exists inside
  a package (aar_sim's src/renderer/). A package's file, aar_NAME/PATH with an extension
  (aar_testing/loop_bag.py, aar_sim/sensor.h), is the end of a file's path under src/aar_NAME/.
  A missing scripts/ path is reported as a missing script. A Markdown link's target
  ([text](target); not a URL, not an #anchor) exists beside the file that links it.
- An option: in code, `scripts/NAME ...` up to the end of its command (`|`, `;`, `&&`, `>`, a
  ` #` comment) names each `--flag` in it, in a synopsis too ([--jobs J]); in prose, scripts/NAME
  followed straight by `--flag [VALUE]` pairs. A script's flags are what its source defines:
  add_argument's, `== "--flag"` and `"--flag" in` in Python, case labels (`--flag)`) and
  `[ "$1" = --flag ]` in bash; with the sources of what it execs or imports from scripts/
  (scripts/run: the campaign driver, scripts/campaign/*.py, all its modes' flags together).
  Only a script whose sources have an argparse parser or a `case "$1"` is checked
  (scripts/build passes its arguments on to catkin); -h and --help are every script's.
- An experiment, config/experiments/NAME.yaml: each name (comma-separated) after --experiments,
  --experiment, --configs (bench-realtime's), --show-experiment (`=` or a space) and
  experiment:=, in code or prose; each `name` in backticks straight after the word experiment
  or experiments (`a`, `b` and `c`); and in a table with a column headed `experiment`, each
  `name` in backticks in that column, or the whole cell when it is one bare name.
Not names: placeholders, that is anything but a lower-case identifier (NAME, E, a,b,...,
<copy>, $w); and what the same line quotes in single quotes ('nonsense', '--bogus': the bad
inputs docs/RELIABILITY.md lists with the refusal that names them). In a path, an upper-case
word other than a .md file's name (NAME, N, DIR), <...>, $var and * stand for any name: the path
counts when a file matches; one with {a,b} or ... in it is not checked. The top folders
.gitignore names (results/, rosbags/cache/) are made by runs: not checked.
Not checked: ROS parameter names (there is no one list to check them against: each stage's
options loader reads its own, config/*.yaml holds only some), roslaunch arguments, the options
of the C++ tools and of scripts with no parser as above, and commands named without scripts/
(plot_integrity.py, make_report)."""
import glob
import os
import re
import subprocess
import sys

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "../.."))
TOPS = ("docs", "src", "config", "launch", "scripts", "rosbags")
PATH = re.compile(r"(?<![\w./$-])((?:%s)/[\w./*<>$+-]*)" % "|".join(TOPS))
PACKAGE_PATH = re.compile(r"(?<![\w./$-])(aar_[a-z_]+)/([\w/.-]*\.[a-z]+)\b")
LINK = re.compile(r"\[[^\]]*\]\(([^)\s]+)\)")
SCRIPT = re.compile(r"(?<![\w./$-])scripts/(\w[\w.-]*)(?![\w/.-])")
EXPERIMENT_FLAG = re.compile(r"(?:--(?:experiments|experiment|configs|show-experiment)[= ]|"
                             r"(?<![\w])experiment:=)(\S+)")
EXPERIMENT_WORD = re.compile(r"\bexperiments?\s+((?:`[^`\s]+`(?:,?\s+(?:and\s+|or\s+)?)?)+)")
NAME = re.compile(r"[a-z][a-z0-9_]*")
PLACEHOLDER = re.compile(r"<[^>/]*>|\$\w+|(?<![A-Za-z0-9])[A-Z][A-Z0-9]*(?![A-Za-z0-9]|\.md)")
FLAG = re.compile(r"--[a-z][a-z0-9-]*")
ENDS = {"|", "||", "&&", ";", ">", ">>", "2>&1", "&"}


def doc_files(root):
    """The Markdown files git knows (tracked or new, not ignored); docs/ and README.md without
    git."""
    try:
        out = subprocess.run(["git", "-C", root, "ls-files", "-co", "--exclude-standard", "--",
                              "*.md"], capture_output=True, text=True, check=True).stdout
        files = [os.path.join(root, f) for f in out.splitlines()]
    except (OSError, subprocess.CalledProcessError):
        files = glob.glob(os.path.join(root, "docs", "**", "*.md"), recursive=True)
        files.append(os.path.join(root, "README.md"))
    return sorted(f for f in files if os.path.isfile(f))


def ignored(root):
    """The top folders .gitignore names (/results/, /rosbags/cache/): made by runs."""
    try:
        with open(os.path.join(root, ".gitignore")) as f:
            return [line.strip().strip("/") for line in f
                    if line.startswith("/") and line.strip().endswith("/")]
    except OSError:
        return []


def segments(text):
    """(kind, text, first line) of a Markdown file: kind "code" for each command of a fenced
    block and each inline span, "prose" for each paragraph with its spans blanked (offsets and
    line breaks kept)."""
    lines = text.split("\n")
    out, i = [], 0
    while i < len(lines):
        fence = re.match(r"\s*(```|~~~)", lines[i])
        if fence:
            j = i + 1
            while j < len(lines) and not lines[j].lstrip().startswith(fence.group(1)):
                j += 1
            command, start = "", i + 2
            for n in range(i + 1, j):
                command += lines[n]
                if lines[n].endswith("\\"):
                    command += "\n"
                    continue
                out.append(("code", command, start))
                command, start = "", n + 2
            i = j + 1
            continue
        j = i
        while j < len(lines) and lines[j].strip() and not re.match(r"\s*(```|~~~)", lines[j]):
            j += 1
        if j == i:
            i += 1
            continue
        paragraph = "\n".join(lines[i:j])
        prose = list(paragraph)
        for m in re.finditer(r"(`+)(.+?)\1", paragraph, re.S):
            out.append(("code", m.group(2), i + 1 + paragraph.count("\n", 0, m.start(2))))
            for k in range(m.start(), m.end()):
                if prose[k] != "\n":
                    prose[k] = " "
        out.append(("prose", "".join(prose), i + 1))
        i = j
    return out


def line_of(segment, start, offset):
    return start + segment.count("\n", 0, offset)


def refused(line, name):
    """The line quotes `name` as a refused input ('nonsense', '--bogus')."""
    return f"'{name}'" in line


class Workspace:
    def __init__(self, root):
        self.root = root
        self.ignored = ignored(root)
        self.experiments = {os.path.basename(p)[:-5] for p in
                            glob.glob(os.path.join(root, "config/experiments/*.yaml"))}
        self.flags_of = {}

    def exists(self, path):
        """`path` (from the root) names a file or folder; placeholders match any name."""
        path = path.rstrip("/")
        if any(path == d or path.startswith(d + "/") for d in self.ignored):
            return True
        candidates = [path]
        if path.startswith("src/"):  # inside a package: aar_sim's src/renderer/
            candidates += [os.path.relpath(p, self.root) + "/" + path for p in
                           glob.glob(os.path.join(self.root, "src", "*", ""))]
        for candidate in candidates:
            if os.path.exists(os.path.join(self.root, candidate)):
                return True
            pattern = PLACEHOLDER.sub("*", candidate)
            if "*" in pattern and glob.glob(os.path.join(self.root, pattern)):
                return True
        return False

    def in_package(self, package, path):
        """`path` is the end of a file's path under src/<package>/ (its include/, scripts/...)."""
        folder = os.path.join(self.root, "src", package)
        return any(os.path.join(base, f).endswith("/" + path)
                   for base, _, files in os.walk(folder) for f in files)

    def flags(self, script):
        """The flags `scripts/<script>` takes, or None when it has no parser to check them by."""
        if script not in self.flags_of:
            self.flags_of[script] = script_flags(os.path.join(self.root, "scripts", script),
                                                 self.root)
        return self.flags_of[script]


def sources(path, root):
    """The files whose code parses `path`'s arguments: itself (a folder: its *.py) and what it
    execs or imports from scripts/."""
    files = sorted(glob.glob(os.path.join(path, "*.py"))) if os.path.isdir(path) else [path]
    found = list(files)
    for f in files:
        try:
            with open(f, errors="replace") as handle:
                text = handle.read()
        except OSError:
            continue
        others = re.findall(r"^\s*exec\b.*?scripts/([\w-]+)", text, re.M)
        others += re.findall(r"^\s*(?:from|import) (\w+)", text, re.M)
        for other in others:
            target = os.path.join(root, "scripts", other)
            if os.path.exists(target) and os.path.abspath(target) != os.path.abspath(path):
                found += sorted(glob.glob(os.path.join(target, "*.py"))) \
                    if os.path.isdir(target) else [target]
    return found


def script_flags(path, root):
    if not os.path.exists(path):
        return None
    flags, parsed = {"-h", "--help"}, False
    for f in sources(path, root):
        try:
            with open(f, errors="replace") as handle:
                text = handle.read()
        except OSError:
            continue
        if "add_argument(" in text:
            parsed = True
        if re.search(r"^\s*case\s+\"?\$\{?1", text, re.M):
            parsed = True
        for call in re.findall(r"add_argument\(([^)]*)", text):  # argparse
            flags.update(re.findall(r"[\"'](--[a-z][a-z0-9-]*)[\"']", call))
        flags.update(re.findall(r"[=!]=\s*[\"'](--[a-z][a-z0-9-]*)[\"']", text))  # argv[0] == "--x"
        flags.update(re.findall(r"[\"'](--[a-z][a-z0-9-]*)[\"']\s+(?:in|==)\b", text))
        for label in re.findall(r"^\s*\(?([-\w|* =]+)\)", text, re.M):  # bash case labels
            flags.update(FLAG.findall(label))
        flags.update(re.findall(r"\]?\s=\s\"?(--[a-z][a-z0-9-]*)\"?\s*\]", text))  # [ "$1" = --x ]
    return flags if parsed else None


def command_flags(segment, start):
    """(offset, flag) of each --flag of a command from `start` (just after scripts/NAME)."""
    found = []
    for m in re.finditer(r"\S+", segment[start:]):
        token = m.group(0)
        if token in ENDS or token.startswith((">", "#", "2>")):
            break
        end = token.endswith(";")
        flag = FLAG.match(token.strip("[]()|`\"'"))
        if flag:
            found.append((start + m.start() + token.index("--"), flag.group(0)))
        if end:
            break
    return found


def prose_flags(segment, start):
    """In prose: the --flag [VALUE] pairs straight after scripts/NAME."""
    found, pair = [], re.compile(r"\s+(--[a-z][a-z0-9-]*)(?:[= ](?!--)[^\s,;)]+)?")
    m = pair.match(segment, start)
    while m:
        found.append((m.start(1), m.group(1)))
        m = pair.match(segment, m.end())
    return found


def check_names(value):
    """The experiment names of a flag's value (a,b,c), placeholders left out."""
    if "..." in value or "/" in value or ".yaml" in value:
        return []
    value = value.strip("`'\"[](),.;:")
    return [n for n in value.split(",") if NAME.fullmatch(n)]


def table_experiments(text):
    """(line, name) of each experiment in a table column headed `experiment`."""
    found, column = [], None
    for number, line in enumerate(text.split("\n"), 1):
        if not line.lstrip().startswith("|"):
            column = None
            continue
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if column is None:
            heads = [c.strip("*_ ").lower() for c in cells]
            column = heads.index("experiment") if "experiment" in heads else -1
            continue
        if column < 0 or column >= len(cells) or set(line) <= set("|-: "):
            continue
        cell = cells[column]
        names = re.findall(r"`([^`]+)`", cell) or [cell]
        found += [(number, n) for n in names if NAME.fullmatch(n)]
    return found


def missing(experiment):
    return f"no experiment {experiment} (config/experiments/{experiment}.yaml)"


def check_file(path, ws):
    with open(path, errors="replace") as f:
        text = f.read()
    lines = text.split("\n")
    where = os.path.relpath(path, ws.root) if path.startswith(ws.root + os.sep) else path
    folder = os.path.dirname(os.path.abspath(path))
    found = set()

    def report(number, what, name):
        if not refused(lines[number - 1], name):
            found.add((number, what))

    for kind, segment, start in segments(text):
        for m in PATH.finditer(segment):
            name = m.group(1).rstrip(".,:;")
            if "{" in name or "..." in name or name.endswith("/.") or not name.strip("/"):
                continue
            if not ws.exists(name):
                what = "no script" if name.startswith("scripts/") else "no file"
                report(line_of(segment, start, m.start(1)), f"{what} {name}", name)
        for m in PACKAGE_PATH.finditer(segment):
            if not ws.in_package(m.group(1), m.group(2)):
                report(line_of(segment, start, m.start()), f"no file {m.group(0)} (in src/"
                       f"{m.group(1)}/)", m.group(0))
        if kind == "prose":
            for m in LINK.finditer(segment):
                target = m.group(1).split("#")[0]
                if not target or re.match(r"[a-z]+:", target):
                    continue
                if not os.path.exists(os.path.join(folder, target)):
                    report(line_of(segment, start, m.start(1)), f"no file {target} (linked)",
                           target)
        for m in SCRIPT.finditer(segment):
            flags = ws.flags(m.group(1))
            if flags is None:
                continue
            named = (command_flags if kind == "code" else prose_flags)(segment, m.end())
            for offset, flag in named:
                if flag not in flags:
                    report(line_of(segment, start, offset), f"scripts/{m.group(1)} has no option "
                           f"{flag}", flag)
        for m in EXPERIMENT_FLAG.finditer(segment):
            for name in check_names(m.group(1)):
                if name not in ws.experiments:
                    report(line_of(segment, start, m.start(1)), missing(name), name)
    for m in EXPERIMENT_WORD.finditer(text):
        for name in re.findall(r"`([^`]+)`", m.group(1)):
            if NAME.fullmatch(name) and name not in ws.experiments:
                report(line_of(text, 1, m.start(1)), missing(name), name)
    for number, name in table_experiments(text):
        if name not in ws.experiments:
            report(number, missing(name), name)
    return [f"{where}:{n}: {what}" for n, what in sorted(found)]


def main(argv):
    files = [os.path.abspath(f) for f in argv[1:]] or doc_files(ROOT)
    unreadable = [f for f in files if not os.path.isfile(f) or not os.access(f, os.R_OK)]
    if unreadable:
        for f in unreadable:
            print(f"check_docs: {f}: not a readable file", file=sys.stderr)
        print(__doc__.splitlines()[1].strip() + "\n" + __doc__.splitlines()[2].strip(),
              file=sys.stderr)
        return 2
    ws, found = Workspace(ROOT), []
    for f in files:
        found += check_file(f, ws)
    print("\n".join(found) if found else f"{len(files)} files, every name exists")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
