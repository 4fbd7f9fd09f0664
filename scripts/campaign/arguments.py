"""Checks shared by the command lines of the scripts in Python that are not the campaign's:
each refuses a bad value at once, naming the flag and the value, and exits 2 ("PROG: --rate
takes a number above 0, not '0'"). The shell scripts' nonnegative and whole are
scripts/lib/preamble.bash's."""
import argparse
import re
import sys

from campaign import workspace

# Decimal, with an exponent if wanted (0.25, 2.5e-1): preamble.bash's number_re.
NUMBER = re.compile(r"([0-9]+\.?[0-9]*|\.[0-9]+)([eE][-+]?[0-9]+)?")


def absolute(path, caller):
    """A path as the caller meant it, as preamble.bash's absolute(): a relative path is the
    caller's, joined as given (not normalised: messages and the files' names quote it as given,
    and tests look for it so)."""
    return path if not path or path.startswith("/") else f"{caller}/{path}"


def refuse(flag, what, value):
    workspace.fail(f"{flag} takes {what}, not '{value}'")


def positive(flag, value, most=None):
    """A number above 0 (e.g. a rate), at most `most` if given."""
    what = "a number above 0" + (f" and at most {most:g}" if most is not None else "")
    if not NUMBER.fullmatch(value) or not 0 < float(value) <= (most if most is not None
                                                                 else float("inf")):
        refuse(flag, what, value)
    return value


def synopsis(doc):
    """The usage lines of a script's docstring: each `  scripts/NAME ...` and the lines that
    continue it (indented further)."""
    lines, on = [], False
    for line in doc.splitlines():
        if line.startswith("  scripts/"):
            on = True
        elif not line.startswith("    "):
            on = False
        if on:
            lines.append(line.strip() if not lines else " " * 5 + line)
    return "\n".join(lines) or None


class Parser(argparse.ArgumentParser):
    """argparse as the bash scripts answered: an unknown argument named, with the usage, and
    exit 2; any other error as `PROG: message`; no abbreviated flags."""

    def __init__(self, prog, doc, who=None, **kw):
        super().__init__(prog=prog, description=doc, allow_abbrev=False, usage=synopsis(doc),
                         formatter_class=argparse.RawDescriptionHelpFormatter, **kw)
        self.who = who or prog  # "two-hosts: netns" names the mode too

    def error(self, message):
        known = "unrecognized arguments: "
        if message.startswith(known):
            print(f"{self.who}: unknown argument '{message[len(known):].split()[0]}'",
                  file=sys.stderr)
            self.print_usage(sys.stderr)
            sys.exit(2)
        needs = re.fullmatch(r"argument (--[\w-]+): expected one argument", message)
        workspace.fail(f"{needs.group(1)} needs a value" if needs else message)
