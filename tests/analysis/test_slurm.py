#!/usr/bin/python3
"""ctest (label distributed): a study run for real on Slurm. Starts a single-node cluster from
Debian's packages in a temporary directory (munged on its own socket, slurmctld and slurmd
with ProctrackType=proctrack/pgid, TaskPlugin=task/none, no accounting), submits the study
with analysis/slurm/submit_study.sh (a job array of 3 shards and a merge job that depends on
them), waits, checks that the merged study equals the study run on one machine, and stops
the daemons it started. Needs root (CI runs as root) and the packages slurmctld, slurmd,
slurm-client and munge (.ci/deps.sh); exit 77 (skipped) without them.
Arguments: PGT_BINARY SOURCE_DIR."""
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time

PGT, SRC = os.path.realpath(sys.argv[1]), sys.argv[2]
NEEDED = ["munged", "slurmctld", "slurmd", "sbatch", "squeue", "scontrol"]
missing = [p for p in NEEDED if not shutil.which(p) and not os.path.exists("/usr/sbin/" + p)]
if missing or os.geteuid() != 0:
    print(f"skipped: needs root and {', '.join(missing) or 'nothing'}")
    sys.exit(77)

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from small_study import SCENE, rows  # noqa: E402


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def sbin(name):
    return shutil.which(name) or "/usr/sbin/" + name


def slurm_conf(t, host):
    """The cluster on loopback: controller and node at 127.0.0.1 by address, so no host name is
    looked up (a root without /etc/hosts, as a fresh debootstrap has, hung every sinfo on DNS)."""
    cpus = os.cpu_count() or 1
    return "\n".join([
        "ClusterName=pgttest", f"SlurmctldHost={host}(127.0.0.1)", "SlurmUser=root",
        "SlurmdUser=root",
        f"SlurmctldPort={free_port()}", f"SlurmdPort={free_port()}",
        f"StateSaveLocation={t}/state", f"SlurmdSpoolDir={t}/spool",
        f"SlurmctldPidFile={t}/slurmctld.pid", f"SlurmdPidFile={t}/slurmd.pid",
        f"SlurmctldLogFile={t}/slurmctld.log", f"SlurmdLogFile={t}/slurmd.log",
        "ProctrackType=proctrack/pgid", "TaskPlugin=task/none",
        "AuthType=auth/munge", f"AuthInfo=socket={t}/munge.socket",
        "CredType=cred/munge", "MpiDefault=none", "ReturnToService=2",
        "SchedulerType=sched/builtin", "SelectType=select/cons_tres",
        "SelectTypeParameters=CR_Core", "AccountingStorageType=accounting_storage/none",
        "JobCompType=jobcomp/none", "JobAcctGatherType=jobacct_gather/none",
        "SlurmctldTimeout=30", "SlurmdTimeout=30", "InactiveLimit=0", "MinJobAge=300",
        f"NodeName={host} NodeAddr=127.0.0.1 CPUs={cpus} State=UNKNOWN",
        f"PartitionName=pgt Nodes={host} Default=YES MaxTime=INFINITE State=UP", ""])


started = []  # (name, pid file or process)


def stop_all(t):
    for name, pidfile in reversed(started):
        try:
            pid = int(open(pidfile).read().split()[0])
            os.kill(pid, signal.SIGTERM)
            for _ in range(50):
                os.kill(pid, 0)
                time.sleep(0.1)
        except (OSError, ValueError):
            pass


def main(t):
    host = socket.gethostname().split(".")[0]
    for sub in ("state", "spool", "study"):
        os.makedirs(os.path.join(t, sub))
    conf = os.path.join(t, "slurm.conf")
    open(conf, "w").write(slurm_conf(t, host))
    env = dict(os.environ, SLURM_CONF=conf)
    # munge: this cluster's own daemon and socket, with a fresh key.
    key = os.path.join(t, "munge.key")
    open(key, "wb").write(os.urandom(1024))
    os.chmod(key, 0o600)
    subprocess.run([sbin("munged"), "--force", f"--socket={t}/munge.socket", f"--key-file={key}",
                    f"--pid-file={t}/munged.pid", f"--log-file={t}/munged.log",
                    f"--seed-file={t}/munged.seed"], check=True)
    started.append(("munged", f"{t}/munged.pid"))
    subprocess.run([sbin("slurmctld"), "-f", conf], check=True, env=env)
    started.append(("slurmctld", f"{t}/slurmctld.pid"))
    subprocess.run([sbin("slurmd"), "-f", conf], check=True, env=env)
    started.append(("slurmd", f"{t}/slurmd.pid"))
    for _ in range(100):  # the node up and idle
        r = subprocess.run(["sinfo", "-h", "-o", "%T"], capture_output=True, text=True, env=env)
        if r.stdout.strip() in ("idle", "mixed"):
            break
        time.sleep(0.3)
    else:
        raise RuntimeError("the node never came up: " + r.stdout + r.stderr)

    scene = os.path.join(t, "scene.json")
    json.dump(SCENE, open(scene, "w"))
    whole = os.path.join(t, "whole")
    subprocess.run([PGT, "sweep", scene, "--out", whole, "--no-report"], check=True,
                   capture_output=True)
    out = os.path.join(t, "study")
    r = subprocess.run([os.path.join(SRC, "analysis/slurm/submit_study.sh"), scene, out, "3", PGT,
                        "--", "--partition=pgt"], capture_output=True, text=True, env=env)
    print(r.stdout + r.stderr)
    if r.returncode != 0:
        raise RuntimeError("submit failed")
    merged = os.path.join(out, "study", "results.csv")
    for _ in range(600):  # the array and the merge done (at most 5 minutes)
        q = subprocess.run(["squeue", "-h"], capture_output=True, text=True, env=env)
        if not q.stdout.strip() and q.returncode == 0:
            break
        time.sleep(0.5)
    ok = os.path.exists(merged) and rows(os.path.dirname(merged)) == rows(whole)
    logs = os.path.join(out, "logs")
    for name in sorted(os.listdir(logs)) if os.path.isdir(logs) else []:
        print(f"--- {name}\n" + open(os.path.join(logs, name)).read()[-1500:])
    print(("ok   " if ok else "FAIL ") + "3 Slurm shards merged = the study on one machine")
    return ok


tmp = tempfile.mkdtemp(prefix="pgt-slurm-")
try:
    ok = main(tmp)
except Exception as e:  # report, then stop the daemons
    print(f"FAIL {e}")
    for log in ("slurmctld.log", "slurmd.log", "munged.log"):
        p = os.path.join(tmp, log)
        if os.path.exists(p):
            print(f"--- {log}\n" + open(p).read()[-3000:])
    ok = False
finally:
    stop_all(tmp)
shutil.rmtree(tmp, ignore_errors=True)
sys.exit(0 if ok else 1)
