"""What the *_error_cost / *_error_chart scripts share: running a measurement tool with its output
echoed and optionally logged with the command line, and reading its CSV (# lines are comments)."""
import csv
import subprocess
import sys


def run_logged(cmd, log_path=None):
    """Runs cmd, echoes its stdout, writes "$ cmd" + stdout to log_path if given; returns the exit code."""
    print(" ".join(cmd), file=sys.stderr)
    out = subprocess.run(cmd, stdout=subprocess.PIPE, text=True)
    sys.stdout.write(out.stdout)
    if log_path:
        with open(log_path, "w") as f:
            f.write("$ " + " ".join(cmd) + "\n" + out.stdout)
    return out.returncode


def rows(path):
    with open(path) as f:
        return list(csv.DictReader(line for line in f if line.strip() and not line.startswith("#")))
