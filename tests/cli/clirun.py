"""What the end-to-end scripts in tests/cli share: the binary and the shared data folder from the
command line, a scratch folder, running the tool, and a tiny test runner.

    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from clirun import BIN, DATA, TMP, data, main, run, test, tmp

    @test
    def something():
        code, out, err = run("info", data("cmu/64_08.bvh"))
        assert code == 0, err

    if __name__ == "__main__":
        sys.exit(main())

usage of every such script: SCRIPT.py MOTIONMAP_BINARY SHARED_DATA_DIR
"""
import os
import shutil
import subprocess
import sys
import tempfile
import traceback

if len(sys.argv) != 3:
    sys.exit(f"usage: {os.path.basename(sys.argv[0])} MOTIONMAP_BINARY SHARED_DATA_DIR")

BIN = os.path.abspath(sys.argv[1])
DATA = os.path.abspath(sys.argv[2])
# One scratch folder a script, named after it (motionmap-cli_test-…), removed when every test
# passed and kept for a look when one failed.
TMP = tempfile.mkdtemp(prefix="motionmap-%s-" % os.path.splitext(os.path.basename(sys.argv[0]))[0])

TESTS = []


def test(fn):
    """Registers `fn` as a test; main() runs them in the order they were defined."""
    TESTS.append(fn)
    return fn


def run(*args, env=None):
    """(exit code, stdout, stderr) of the tool run with `args`."""
    p = subprocess.run([BIN, *args], capture_output=True, text=True, timeout=300, env=env)
    return p.returncode, p.stdout, p.stderr


def data(rel):
    """A file of the shared data, by its path under ../shared/data."""
    return os.path.join(DATA, rel)


def tmp(*parts):
    """A path in the scratch folder."""
    return os.path.join(TMP, *parts)


def needs(*rels):
    """Whether the shared data files `rels` are all there (else says which one is not)."""
    for rel in rels:
        if not os.path.exists(data(rel)):
            print(f"  skipped: {rel} absent from the shared data")
            return False
    return True


def read_map(path):
    """(comment lines, header, rows as lists of strings) of a map CSV."""
    with open(path) as f:
        lines = f.read().splitlines()
    comments = [line for line in lines if line.startswith("#")]
    rows = [line.split(",") for line in lines if not line.startswith("#")]
    return comments, rows[0], rows[1:]


def main():
    """Runs every test; exit status 1 when one failed."""
    passed = failed = 0
    for fn in TESTS:
        try:
            fn()
            passed += 1
            print(f"PASS {fn.__name__}")
        except Exception:
            failed += 1
            print(f"FAIL {fn.__name__}")
            traceback.print_exc()
    print(f"{passed} passed, {failed} failed")
    if failed:
        print(f"scratch files kept in {TMP}")
    else:
        shutil.rmtree(TMP, ignore_errors=True)
    return 1 if failed else 0
