#!/usr/bin/python3
"""stltopo info over a corpus on a Dask distributed cluster: the native CLI, once per file.

usage: /usr/bin/python3 scripts/dask_corpus.py (SCHEDULER | --local N) STLTOPO [--batch K]
           [INFO FLAGS...] [--list LIST]... FILE|DIR...

  SCHEDULER   the address of a running scheduler (tcp://host:8786); every worker must be
              able to run STLTOPO and read the files under the same paths.
  --local N   a LocalCluster of N worker processes on this machine instead.
  STLTOPO     the native CLI (build/stltopo).
  --batch K   files per task (default 1): one stltopo process reports K files.
  INFO FLAGS  passed to every `stltopo info` (--json, --shells, --defects, --intersections,
              --tolerance D, --max-defects N, ...); --jobs and --max-memory are not (the workers
              are the jobs).

The inputs are expanded as `stltopo info` expands them (a DIR is walked for *.stl files,
any case, sorted bytewise by path, links to directories not followed; --list reads FILE and
DIR arguments one per line, '-' for standard input), and the output is what
`stltopo info FLAGS INPUTS...` prints on one machine: the same bytes on standard output and
standard error, in the same order, exit status 1 when a file failed (2 on usage errors).
Needs Debian's python3-distributed (run it with /usr/bin/python3).
"""
import logging
import os
import stat
import subprocess
import sys

USAGE = __doc__.split("\n\n")[1] + "\n"
VALUE_FLAGS = {"--max-defects", "--max-pairs", "--tolerance", "--max-triangles", "--max-bytes"}
BOOL_FLAGS = {"--json", "--no-topology", "--shells", "--defects", "--intersections"}


def usage_error(message):
    sys.stderr.write("dask_corpus: " + message + "\n" + USAGE)
    sys.exit(2)


def is_stl_name(name):
    return len(name) >= 4 and name[-4:].lower() == b".stl"


def walk(root, out):
    """The *.stl files under the directory root, as tools/cli.cpp walk(): (path, is_error)."""
    found = []
    dirs = [root]
    while dirs:
        d = dirs.pop()
        try:
            entries = list(os.scandir(d))
        except OSError:
            found.append((d, True))  # the CLI reports it as a file that cannot be opened
            continue
        prefix = d if d.endswith(b"/") else d + b"/"
        for e in entries:
            p = prefix + e.name
            try:
                if e.is_dir(follow_symlinks=False):
                    dirs.append(p)
                    continue
                regular = e.is_file(follow_symlinks=False)
                link = e.is_symlink()
            except OSError:
                continue  # gone since the directory was read
            if not is_stl_name(e.name):
                continue
            if link:
                try:
                    regular = stat.S_ISREG(os.stat(p).st_mode)
                except OSError:
                    regular = True  # a broken link: reported as a file that cannot be opened
            if regular:
                found.append((p, False))
    found.sort(key=lambda f: f[0])  # bytes: bytewise
    out.extend(found)


def expand(arg, out):
    if arg == b"-":
        usage_error("standard input ('-') cannot be sent to the workers; use --list - for a list of files")
    try:
        is_dir = stat.S_ISDIR(os.stat(arg).st_mode)
    except (OSError, ValueError):
        is_dir = False
    if is_dir:
        walk(arg, out)
    else:
        out.append((arg, False))


def read_list(name, out):
    try:
        if name == b"-":
            data = sys.stdin.buffer.read()
        else:
            with open(name, "rb") as f:
                data = f.read()
    except OSError as e:
        sys.stderr.write("stltopo: cannot read the list %s: %s\n" % (os.fsdecode(name), e.strerror))
        sys.exit(2)
    for number, line in enumerate(data.split(b"\n"), 1):
        if line.endswith(b"\r"):
            line = line[:-1]
        if b"\0" in line:
            sys.stderr.write("stltopo: the list %s has a NUL byte on line %d\n" % (os.fsdecode(name), number))
            sys.exit(2)
        if line:
            expand(line, out)


def run_stltopo(binary, flags, paths):
    """On a worker: `stltopo info FLAGS -- PATHS...`: (stdout, stderr, exit status)."""
    try:
        r = subprocess.run([binary, "info", *flags, "--", *paths], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    except OSError as e:
        return b"", ("dask_corpus: cannot run %s on a worker: %s\n" % (os.fsdecode(binary), e.strerror)).encode(), 127
    return r.stdout, r.stderr, r.returncode


def main(argv):
    argv = [os.fsencode(a) for a in argv]
    if len(argv) < 2:
        usage_error("needs a scheduler (or --local N) and the stltopo binary")
    i = 0
    local = None
    if argv[0] == b"--local":
        try:
            local = int(argv[1])
        except ValueError:
            local = 0
        if not 1 <= local <= 256:
            usage_error("bad --local '%s' (1 to 256)" % os.fsdecode(argv[1]))
        i = 2
    else:
        scheduler = os.fsdecode(argv[0])
        i = 1
    if i >= len(argv):
        usage_error("needs the stltopo binary")
    binary = argv[i]
    i += 1
    batch = 1
    flags, inputs = [], []  # inputs: (path, is_list)
    end_of_options = False
    while i < len(argv):
        s = argv[i]
        i += 1
        if end_of_options or s == b"-" or not s.startswith(b"-"):
            inputs.append((s, False))
        elif s == b"--":
            end_of_options = True
        elif s in (b"--batch", b"--list") or os.fsdecode(s) in VALUE_FLAGS:
            if i >= len(argv):
                usage_error("%s needs a value" % os.fsdecode(s))
            v = argv[i]
            i += 1
            if s == b"--batch":
                batch = int(v) if v.isdigit() and 1 <= int(v) <= 100000 else usage_error("bad --batch '%s'" % os.fsdecode(v))
            elif s == b"--list":
                inputs.append((v, True))
            else:
                flags += [s, v]
        elif os.fsdecode(s) in BOOL_FLAGS:
            flags.append(s)
        elif s == b"--jobs":
            usage_error("--jobs is the cluster's: one task per worker thread (--local N, dask-worker --nworkers)")
        elif s == b"--max-memory":
            usage_error("--max-memory is the cluster's: a worker's memory (dask-worker --memory-limit)")
        else:
            usage_error("unknown option '%s'" % os.fsdecode(s))
    if not inputs:
        usage_error("no input files")
    if sum(1 for p, is_list in inputs if is_list and p == b"-") > 1:
        usage_error("'--list -' reads standard input: no other input can")

    # The flags are checked once, here, when the binary runs on this machine: a usage error
    # stops before the cluster starts (exit 2, the CLI's own message).
    if os.access(binary, os.X_OK):
        r = subprocess.run([binary, "info", *flags, "--list", "/dev/null"], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        if r.returncode != 0:
            sys.stderr.buffer.write(r.stderr)
            return r.returncode
    files = []
    for p, is_list in inputs:
        if is_list:
            read_list(p, files)
        else:
            expand(p, files)

    from distributed import Client, LocalCluster  # Debian python3-distributed

    cluster = None
    if local is not None:
        # Only the reports go to stdout and stderr: Dask's own messages are silenced (a
        # LocalCluster's shutdown can log an ERROR line about a worker the scheduler has
        # already dropped, which is not a failure of any file).
        logging.getLogger("distributed").setLevel(logging.CRITICAL)
        cluster = LocalCluster(n_workers=local, threads_per_worker=1, processes=True, dashboard_address=None,
                               silence_logs=logging.CRITICAL)
        client = Client(cluster)
    else:
        client = Client(scheduler)
    rc = 0
    try:
        # A directory that could not be read is reported by the binary on this machine (it
        # prints the same error line the serial run prints); every file goes to the cluster,
        # in batches of `batch` files, and the results are printed in input order.
        tasks = []
        k = 0
        while k < len(files):
            if files[k][1]:
                tasks.append(("here", [files[k][0]]))
                k += 1
                continue
            paths = []
            while k < len(files) and not files[k][1] and len(paths) < batch:
                paths.append(files[k][0])
                k += 1
            tasks.append(("cluster", client.submit(run_stltopo, binary, flags, paths, pure=False)))
        for where, task in tasks:
            if where == "here":
                out, err, code = run_stltopo(binary, flags, task)
            else:
                out, err, code = task.result()
                task.release()
            sys.stdout.buffer.write(out)
            if err:
                sys.stdout.buffer.flush()
                sys.stderr.buffer.write(err)
                sys.stderr.buffer.flush()
            if code == 127 and not out:
                return 2  # the binary cannot run: a setup error, not a file's
            if code != 0:
                rc = 1
                if code < 0:
                    sys.stdout.buffer.flush()
                    sys.stderr.write("dask_corpus: stltopo stopped by signal %d\n" % -code)
    finally:
        sys.stdout.buffer.flush()
        client.close()
        if cluster is not None:
            cluster.close()
    return rc


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
