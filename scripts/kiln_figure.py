"""What kiln's figure scripts share (plot_case.py for `kiln plot`, plot_study.py for the studies): how a
figure is written and how a script ends, so that kiln reads every outcome the same way
(src/base/figure_script.h). A script's exit status is one of kiln's (README "Exit codes"):

  0  the figure is written (into TARGET.tmp, renamed to TARGET);
  2  bad input (the script's own arguments or files): one line;
  4  the figure could not be written (no room, no permission, matplotlib missing): one line naming
     the file and the cause; nothing is left under either name;
  6  a defect of the script's: one line naming the exception and where, instead of a traceback.

Issue 28's campaign: a full disk (kiln plot, kiln order) and a fitted order that was null (kiln order)
printed Python tracebacks, then blamed matplotlib; kiln order exited 0."""
import os
import sys
import traceback

BAD_INPUT = 2
OUTPUT_FAILED = 4  # kiln's exit code of an output that could not be written (src/base/error.h)
DEFECT = 6


def fail(status, message):
    """Ends the script with kiln's exit `status` and `message` as its one line on standard error."""
    print(f"error: {message}", file=sys.stderr)
    sys.exit(status)


def pyplot(target):
    """matplotlib's pyplot on the Agg backend (no display); one line and exit 4 without matplotlib."""
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError as e:
        fail(OUTPUT_FAILED, f"cannot draw {target}: {e} (it needs Debian's /usr/bin/python3 with matplotlib: "
                            "apt-get install python3-matplotlib)")
    return plt


def save(fig, target, **options):
    """Writes `fig` as the PNG `target` through target.tmp; returns 0, or 4 after one line saying why not."""
    tmp = target + ".tmp"
    try:
        fig.savefig(tmp, format="png", **options)
        os.replace(tmp, target)
    except OSError as e:  # a full disk, no permission: one line, not a traceback
        if os.path.exists(tmp):
            os.remove(tmp)
        print(f"error: cannot write {tmp}: {e.strerror or e}", file=sys.stderr)
        return OUTPUT_FAILED
    except BaseException:
        if os.path.exists(tmp):
            os.remove(tmp)
        raise
    return 0


def run(main, target):
    """Runs `main` (returning an exit status) as a figure script's body and exits with its status. An
    exception it lets out is a defect of the script's: one line with the exception and the script's
    line that raised it, exit 6, no traceback."""
    try:
        status = main()
    except SystemExit:
        raise
    except Exception as e:  # noqa: BLE001 - every defect ends the same way
        here = os.path.dirname(os.path.abspath(__file__))
        frames = [f for f in traceback.extract_tb(e.__traceback__) if os.path.dirname(os.path.abspath(f.filename)) == here]
        where = f" at {os.path.basename(frames[-1].filename)}:{frames[-1].lineno} in {frames[-1].name}" if frames else ""
        text = str(e).splitlines()[0][:200] if str(e) else ""
        fail(DEFECT, f"cannot draw {target}: {type(e).__name__}{': ' + text if text else ''}{where} "
                     "(a defect of kiln's figure scripts; please report it)")
    sys.exit(status or 0)
