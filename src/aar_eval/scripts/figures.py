"""What the plotting scripts share: matplotlib imported only when there is something to draw (a
run that failed before its first frame ends without its second of start-up), and a figure saved
whole or not at all, the failure named (a full disk leaves no half PNG and no traceback)."""
import os
import sys


def pyplot():
    """matplotlib's pyplot on the Agg backend."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot
    return matplotlib.pyplot


def save(fig, path, prog):
    """Saves `fig` as `path`, then closes it; on a failed write removes what was written, says
    why on stderr and exits 1."""
    try:
        fig.savefig(path)
    except OSError as e:
        try:
            os.remove(path)
        except OSError:
            pass
        print(f"{prog}: cannot write {path}: {e.strerror or e}", file=sys.stderr)
        sys.exit(1)
    finally:
        pyplot().close(fig)
