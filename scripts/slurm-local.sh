#!/usr/bin/env bash
# slurm-local.sh: a single-node Slurm cluster on this machine, for tests and for trying
# `rotorshunt study slurm`. Debian's packages; no systemd, no cgroups, no accounting database.
#
# Usage:
#   scripts/slurm-local.sh up     [DIR]   install (if missing), configure and start; print the
#                                          `export SLURM_CONF=DIR/slurm.conf` line on stdout
#   scripts/slurm-local.sh down   [DIR]   cancel this cluster's jobs, stop its daemons
#   scripts/slurm-local.sh status [DIR]   daemons, sinfo and squeue
#   scripts/slurm-local.sh install [DIR]  install the packages only (if missing); `up`
#                                          then starts at once (.ci/run does this early)
#   scripts/slurm-local.sh help
#
#   DIR defaults to /tmp/rotorshunt-slurm. Everything the cluster writes lives there:
#   slurm.conf, the munge key and socket, daemon logs and pid files, the controller's
#   state, the slurmd spool and the job-completion log jobcomp.log.
#
#   Typical use:   eval "$(scripts/slurm-local.sh up)"   # sets SLURM_CONF in this shell
#                  sbatch --array=0-3 job.sh; squeue; cat /tmp/rotorshunt-slurm/jobcomp.log
#                  scripts/slurm-local.sh down
#
# `up` and `down` need root (daemons run as root, packages come from apt-get); `status`
# does not. Both are idempotent: `up` on a running cluster only checks it is healthy;
# `down` with nothing running does nothing. Progress goes to stderr, so only the export
# line reaches stdout.
#
# Environment (all optional):
#   SLURM_LOCAL_TIMEOUT      seconds `up` waits for the node to become idle (default 90)
#   SLURM_LOCAL_CTLD_PORT    slurmctld's TCP port, reached on 127.0.0.1 (default 6817)
#   SLURM_LOCAL_SLURMD_PORT  slurmd's TCP port, reached on 127.0.0.1 (default 6818)
#
# Exit status: 0 done; 1 the cluster could not be brought up or stopped (the message says
# why, with the daemon logs' tails); 2 bad usage, not root, or DIR holds files that are not
# this script's. `status` exits 0 when all three daemons run and 1 otherwise.
#
# Details, measured times and pitfalls: scripts/slurm-local.md.
set -euo pipefail

readonly PACKAGES=(slurmctld slurmd slurm-client munge)
readonly DEFAULT_DIR=/tmp/rotorshunt-slurm
# The file that marks DIR as this script's; DIR is never written without it.
readonly MARKER=.rotorshunt-slurm-local
# Node and partition names used in slurm.conf and by `slurmd -N`.
readonly NODE=localhost
readonly PARTITION=local
# Environment variable set on the daemons only, so that `down` finds one whose pid file was
# lost.
readonly DAEMON_TAG=ROTORSHUNT_SLURM_LOCAL_DIR
# Seconds a daemon gets to exit after SIGTERM before SIGKILL: slurmctld saves its state on
# SIGTERM, 1-2 s here; a margin for a loaded machine.
readonly STOP_GRACE=15
# Seconds `down` waits for cancelled jobs to leave the running/completing states; slurm.conf
# sets KillWait=5 (SIGTERM to SIGKILL of a cancelled job), so this leaves ample margin.
readonly CANCEL_WAIT=30
# Seconds apt-get waits for a dpkg lock held by another install on the same machine.
readonly APT_LOCK_WAIT=300

TIMEOUT=${SLURM_LOCAL_TIMEOUT:-90}
# Set while a policy-rc.d made by this script exists.
MADE_POLICY=0
# Daemons this `up` started, "PIDFILE NAME" each: stopped again if `up` fails.
STARTED=()
# Epoch seconds when `up` started slurmd (0: it was already running).
SLURMD_STARTED=0
CTLD_PORT=${SLURM_LOCAL_CTLD_PORT:-6817}
SLURMD_PORT=${SLURM_LOCAL_SLURMD_PORT:-6818}

say() { printf 'slurm-local: %s\n' "$*" >&2; }
die() { # die CODE MESSAGE...
    local code=$1
    shift
    printf 'slurm-local: error: %s\n' "$*" >&2
    exit "$code"
}
usage() { sed -n '2,/^set -euo pipefail/{/^set -euo/d;s/^# \{0,1\}//;p}' "$0" >&2; }
elapsed() { echo "$((SECONDS - $1)) s"; }

need_root() {
    [[ $(id -u) -eq 0 ]] && return 0
    die 2 "'$1' must run as root: it installs Debian packages with apt-get and starts" \
        "munged, slurmctld and slurmd as root (SlurmUser=root). Run it with sudo, or as root" \
        "in the container; 'status' works as any user."
}

check_number() { # check_number NAME VALUE MAX
    [[ $2 =~ ^[0-9]{1,9}$ && $2 -gt 0 && $2 -le $3 ]] ||
        die 2 "$1 must be an integer from 1 to $3, got '$2'"
}

# ---------------------------------------------------------------------------- paths

set_paths() {
    local arg=${1:-$DEFAULT_DIR}
    [[ -n $arg ]] || die 2 "DIR is empty"
    DIR=$(realpath -m -- "$arg")
    [[ $DIR != / ]] || die 2 "DIR must not be /"
    CONF=$DIR/slurm.conf
    MUNGE_DIR=$DIR/munge
    MUNGE_KEY=$MUNGE_DIR/munge.key
    MUNGE_SOCKET=$MUNGE_DIR/munge.socket
    MUNGE_PID=$MUNGE_DIR/munged.pid
    MUNGE_LOG=$MUNGE_DIR/munged.log
    CTLD_PID=$DIR/slurmctld.pid
    CTLD_LOG=$DIR/slurmctld.log
    SLURMD_PID=$DIR/slurmd.pid
    SLURMD_LOG=$DIR/slurmd.log
    JOBCOMP=$DIR/jobcomp.log
}

# DIR must be new, empty, or already this script's: a user's folder is never written into.
claim_dir() {
    if [[ -e $DIR && ! -d $DIR ]]; then
        die 2 "$DIR exists and is not a folder; give another DIR"
    fi
    if [[ -d $DIR && ! -e $DIR/$MARKER ]] && [[ -n $(ls -A -- "$DIR") ]]; then
        die 2 "$DIR is not empty and was not made by this script (no $MARKER in it);" \
            "nothing was written. Give a new or empty DIR."
    fi
    mkdir -p -- "$DIR" "$DIR/state" "$DIR/spool" "$MUNGE_DIR"
    # munged refuses a socket folder that others can write into or cannot enter.
    chmod 0755 "$DIR" "$DIR/state" "$DIR/spool" "$MUNGE_DIR"
    [[ -e $DIR/$MARKER ]] || echo "single-node Slurm of scripts/slurm-local.sh" >"$DIR/$MARKER"
}

# ---------------------------------------------------------------------------- processes

# Prints the pid recorded in FILE if that process runs and its name is NAME; else fails.
running_pid() { # running_pid FILE NAME
    local pid
    [[ -r $1 ]] || return 1
    pid=$(tr -dc '0-9' <"$1")
    [[ -n $pid && -r /proc/$pid/comm ]] || return 1
    [[ $(</proc/"$pid"/comm) == "$2" ]] || return 1
    exited "$pid" && return 1
    echo "$pid"
}

# Field N (3 = state, 4 = parent pid) of /proc/PID/stat, read after the parenthesised
# command name, which may itself hold spaces.
stat_field() { # stat_field PID N
    local line fields
    line=$(cat "/proc/$1/stat" 2>/dev/null) || return 1
    read -r -a fields <<<"${line##*) }"
    [[ -n ${fields[$2 - 3]:-} ]] || return 1
    echo "${fields[$2 - 3]}"
}

# True when PID has exited (gone from /proc, or a zombie not yet reaped: pid 1 in a
# container need not reap orphans at once).
exited() { # exited PID
    local state
    state=$(stat_field "$1" 3) || return 0
    [[ $state == Z || $state == X ]]
}

# SIGTERM, then SIGKILL after STOP_GRACE seconds; removes the pid file.
stop_pidfile() { # stop_pidfile FILE NAME
    local pid i
    if pid=$(running_pid "$1" "$2"); then
        say "stopping $2 (pid $pid)"
        kill -TERM "$pid" 2>/dev/null || true
        for ((i = 0; i < STOP_GRACE * 10; i++)); do
            exited "$pid" && break
            sleep 0.1
        done
        if ! exited "$pid"; then
            say "$2 (pid $pid) ignored SIGTERM for ${STOP_GRACE} s; sending SIGKILL"
            kill -KILL "$pid" 2>/dev/null || true
            for ((i = 0; i < 50; i++)); do
                exited "$pid" && break
                sleep 0.1
            done
        fi
    fi
    rm -f -- "$1"
}

# A step daemon of this cluster: slurmstepd writes its process title over its environment,
# so it is recognised by its working folder (slurmd's, DIR) or its open slurmd log instead.
is_our_stepd() { # is_our_stepd /proc/PID
    local fd
    [[ $(cat "$1/comm" 2>/dev/null) == slurmstepd ]] || return 1
    [[ $(readlink "$1/cwd" 2>/dev/null) == "$DIR" ]] && return 0
    for fd in "$1"/fd/*; do
        [[ $(readlink "$fd" 2>/dev/null) == "$SLURMD_LOG" ]] && return 0
    done
    return 1
}

# Pids of the processes of this DIR's cluster that outlived their daemons, with all their
# descendants: daemons (DAEMON_TAG in their environment), step daemons (is_our_stepd) and
# job processes (SLURM_JOB_ID set and SLURM_CONF pointing at this DIR). Never this script
# or its ancestors.
leftover_pids() {
    local p pid env ppid state
    local -A keep=() seed=() parent_of=()
    pid=$$
    while [[ $pid -gt 1 ]]; do
        keep[$pid]=1
        pid=$(stat_field "$pid" 4) || break
    done
    for p in /proc/[0-9]*; do
        pid=${p#/proc/}
        [[ -n ${keep[$pid]:-} ]] && continue
        env=$(tr '\0' '\n' 2>/dev/null <"$p/environ") || continue
        if grep -qxF "$DAEMON_TAG=$DIR" <<<"$env" || is_our_stepd "$p" ||
            { grep -qxF "SLURM_CONF=$CONF" <<<"$env" && grep -q '^SLURM_JOB_ID=' <<<"$env"; }; then
            seed[$pid]=1
        fi
    done
    local -A zombie=()
    while read -r pid ppid state; do
        parent_of[$pid]=$ppid
        [[ $state == Z* ]] && zombie[$pid]=1
    done < <(ps -e -o pid=,ppid=,stat=)
    for pid in "${!parent_of[@]}"; do
        [[ -n ${keep[$pid]:-} || -n ${zombie[$pid]:-} ]] && continue
        p=$pid
        while [[ -n $p && $p -gt 1 ]]; do
            if [[ -n ${seed[$p]:-} ]]; then
                echo "$pid"
                break
            fi
            p=${parent_of[$p]:-}
        done
    done
}

# ---------------------------------------------------------------------------- install

installed() { # installed PACKAGE
    [[ $(dpkg-query -W -f='${db:Status-Status}' "$1" 2>/dev/null) == installed ]]
}

install_packages() {
    local missing=() p t0=$SECONDS
    for p in "${PACKAGES[@]}"; do installed "$p" || missing+=("$p"); done
    [[ ${#missing[@]} -eq 0 ]] && return 0
    command -v apt-get >/dev/null ||
        die 1 "packages missing (${missing[*]}) and there is no apt-get: this script needs" \
            "Debian or a derivative (Debian 12 ships Slurm 22.05)"
    say "installing ${missing[*]} with apt-get"
    # Without systemd the packages' init scripts would start munged and slurmd with the
    # system's default configuration; policy-rc.d answering 101 forbids that during the
    # install (Debian's documented mechanism). Only a file this script made is removed.
    if [[ ! -e /usr/sbin/policy-rc.d ]]; then
        printf '#!/bin/sh\n# temporary, from slurm-local.sh\nexit 101\n' >/usr/sbin/policy-rc.d
        chmod 0755 /usr/sbin/policy-rc.d
        MADE_POLICY=1
    fi
    local apt=(apt-get -y -q --no-install-recommends -o "DPkg::Lock::Timeout=$APT_LOCK_WAIT")
    if ! DEBIAN_FRONTEND=noninteractive "${apt[@]}" install "${missing[@]}" >"$DIR/apt.log" 2>&1; then
        say "apt-get install failed (tail of $DIR/apt.log below); running apt-get update and retrying"
        tail -n 5 "$DIR/apt.log" >&2
        DEBIAN_FRONTEND=noninteractive apt-get -q -o "DPkg::Lock::Timeout=$APT_LOCK_WAIT" update \
            >>"$DIR/apt.log" 2>&1 || true
        DEBIAN_FRONTEND=noninteractive "${apt[@]}" install "${missing[@]}" >>"$DIR/apt.log" 2>&1 ||
            die 1 "apt-get install ${missing[*]} failed after apt-get update; last lines of" \
                "$DIR/apt.log:"$'\n'"$(tail -n 15 "$DIR/apt.log")"
    fi
    if [[ $MADE_POLICY -eq 1 ]]; then
        rm -f /usr/sbin/policy-rc.d
        MADE_POLICY=0
    fi
    say "installed ${missing[*]} in $(elapsed "$t0")"
}

# ---------------------------------------------------------------------------- config

real_memory_mib() {
    # What slurmd itself detects (slurmd -C), so the node never registers with less memory
    # than configured (that would drain it); /proc/meminfo's MemTotal as a fallback.
    local m
    m=$(slurmd -C 2>/dev/null | tr ' ' '\n' | sed -n 's/^RealMemory=//p' | head -n 1) || true
    if [[ ! $m =~ ^[0-9]+$ || $m -eq 0 ]]; then
        m=$(awk '/^MemTotal:/ {print int($2 / 1024)}' /proc/meminfo)
    fi
    echo "$m"
}

# slurm.conf for one node, localhost. Plugins chosen to need neither systemd nor cgroups
# nor a database; see scripts/slurm-local.md for each choice.
write_conf() { # write_conf FILE
    local cpus mem
    cpus=$(nproc)
    mem=$(real_memory_mib)
    cat >"$1" <<EOF
# Written by scripts/slurm-local.sh (rewritten by every 'up'): a single-node test cluster.
ClusterName=rotorshunt-local
SlurmctldHost=$NODE(127.0.0.1)
SlurmctldPort=$CTLD_PORT
SlurmdPort=$SLURMD_PORT
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$MUNGE_SOCKET
CredType=cred/munge
StateSaveLocation=$DIR/state
SlurmdSpoolDir=$DIR/spool
SlurmctldPidFile=$CTLD_PID
SlurmdPidFile=$SLURMD_PID
SlurmctldLogFile=$CTLD_LOG
SlurmdLogFile=$SLURMD_LOG
SlurmctldDebug=info
SlurmdDebug=info
# No systemd, no cgroups: processes tracked by parent pid, no task binding.
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
# No accounting database: finished jobs are read from the job-completion text file.
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/filetxt
JobCompLoc=$JOBCOMP
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/backfill
MpiDefault=none
SwitchType=switch/none
ReturnToService=2
MailProg=/bin/true
# A cancelled task gets SIGTERM, then SIGKILL 5 s later (default 30 s).
KillWait=5
# Finished jobs stay visible to squeue and scontrol for 300 s.
MinJobAge=300
NodeName=$NODE NodeAddr=127.0.0.1 NodeHostname=$NODE CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=$PARTITION Nodes=$NODE Default=YES MaxTime=INFINITE State=UP
EOF
}

# ---------------------------------------------------------------------------- daemons

log_tails() {
    local f
    for f in "$MUNGE_LOG" "$CTLD_LOG" "$SLURMD_LOG"; do
        printf '\n--- last lines of %s ---\n' "$f"
        if [[ -r $f ]]; then tail -n 15 "$f"; else echo "(no such file)"; fi
    done
}

start_munged() {
    if running_pid "$MUNGE_PID" munged >/dev/null; then return 0; fi
    if [[ ! -s $MUNGE_KEY ]]; then
        say "creating the munge key $MUNGE_KEY"
        mungekey --create --keyfile "$MUNGE_KEY"
    fi
    chmod 0400 "$MUNGE_KEY"
    # A socket left by a killed munged makes a new one refuse to start.
    rm -f -- "$MUNGE_SOCKET" "$MUNGE_SOCKET.lock"
    say "starting munged"
    env "$DAEMON_TAG=$DIR" munged --socket "$MUNGE_SOCKET" --key-file "$MUNGE_KEY" \
        --pid-file "$MUNGE_PID" --log-file "$MUNGE_LOG" --seed-file "$MUNGE_DIR/munged.seed" \
        --origin 127.0.0.1 ||
        die 1 "munged did not start$(log_tails)"
    STARTED+=("$MUNGE_PID munged")
    if ! munge -n -S "$MUNGE_SOCKET" </dev/null | unmunge -S "$MUNGE_SOCKET" >/dev/null 2>&1; then
        die 1 "munged runs but a credential does not round-trip through $MUNGE_SOCKET$(log_tails)"
    fi
}

# Fails with a clear message when another program (often a second cluster) listens on PORT.
port_free() { # port_free PORT WHAT
    [[ -z $(ss -Hltn "sport = :$1" 2>/dev/null) ]] && return 0
    die 1 "TCP port $1 ($2) is already in use by another program, maybe a cluster in another" \
        "DIR. Stop it, or choose free ports with SLURM_LOCAL_CTLD_PORT and" \
        "SLURM_LOCAL_SLURMD_PORT."
}

start_slurm() {
    if ! running_pid "$CTLD_PID" slurmctld >/dev/null; then
        port_free "$CTLD_PORT" slurmctld
        say "starting slurmctld"
        STARTED+=("$CTLD_PID slurmctld")
        env "$DAEMON_TAG=$DIR" SLURM_CONF="$CONF" slurmctld -f "$CONF" ||
            die 1 "slurmctld did not start$(log_tails)"
    fi
    if ! running_pid "$SLURMD_PID" slurmd >/dev/null; then
        port_free "$SLURMD_PORT" slurmd
        SLURMD_STARTED=$(date +%s)
        say "starting slurmd"
        STARTED+=("$SLURMD_PID slurmd")
        env "$DAEMON_TAG=$DIR" SLURM_CONF="$CONF" slurmd -f "$CONF" -N "$NODE" ||
            die 1 "slurmd did not start$(log_tails)"
    fi
}

stop_slurm() {
    stop_pidfile "$SLURMD_PID" slurmd
    stop_pidfile "$CTLD_PID" slurmctld
}

# Epoch seconds of the node's last slurmd registration (SlurmdStartTime), 0 if unknown.
slurmd_registered_at() {
    local t
    t=$(SLURM_CONF=$CONF scontrol -o show node "$NODE" 2>/dev/null |
        tr ' ' '\n' | sed -n 's/^SlurmdStartTime=//p') || true
    date -d "$t" +%s 2>/dev/null || echo 0
}

# Waits for the node to be usable: idle on a fresh cluster, mixed or allocated when `up`
# is run again while jobs run. The controller restores the node's last state from its
# state files, so after a restart it reports `idle` before the new slurmd has registered:
# the wait also requires a registration no older than the slurmd just started.
wait_for_node() {
    local t0=$SECONDS state=""
    while ((SECONDS - t0 < TIMEOUT)); do
        state=$(SLURM_CONF=$CONF sinfo -h -n "$NODE" -o %T 2>/dev/null | head -n 1) || state=""
        case $state in
        idle | mixed | allocated | completing)
            [[ $(slurmd_registered_at) -ge $SLURMD_STARTED ]] && return 0
            ;;
        esac
        if ! running_pid "$CTLD_PID" slurmctld >/dev/null; then
            die 1 "slurmctld exited while starting$(log_tails)"
        fi
        if ! running_pid "$SLURMD_PID" slurmd >/dev/null; then
            die 1 "slurmd exited while starting$(log_tails)"
        fi
        sleep 0.5
    done
    die 1 "node $NODE is not idle after ${TIMEOUT} s (state '${state:-no answer}')." \
        "sinfo -R says:"$'\n'"$(SLURM_CONF=$CONF sinfo -R 2>&1 || true)$(log_tails)"
}

# ---------------------------------------------------------------------------- commands

# On any exit of `up`: remove a policy-rc.d this script made and, when `up` failed, stop
# the daemons it started (newest first) so that a failed `up` leaves nothing running.
up_exit() {
    local rc=$? i
    [[ $MADE_POLICY -eq 1 ]] && rm -f /usr/sbin/policy-rc.d
    if [[ $rc -ne 0 && ${#STARTED[@]} -gt 0 ]]; then
        say "'up' failed; stopping the daemons it started (logs kept in $DIR)"
        for ((i = ${#STARTED[@]} - 1; i >= 0; i--)); do
            # shellcheck disable=SC2086  # "PIDFILE NAME"
            stop_pidfile ${STARTED[i]}
        done
    fi
}

cmd_up() {
    local t0=$SECONDS t1
    need_root up
    trap up_exit EXIT
    check_number SLURM_LOCAL_TIMEOUT "$TIMEOUT" 86400
    check_number SLURM_LOCAL_CTLD_PORT "$CTLD_PORT" 65535
    check_number SLURM_LOCAL_SLURMD_PORT "$SLURMD_PORT" 65535
    claim_dir
    install_packages
    t1=$SECONDS
    write_conf "$CONF.new"
    if [[ -e $CONF ]] && ! cmp -s "$CONF" "$CONF.new"; then
        # A changed machine (CPUs, memory) or port: the daemons must read the new file.
        say "slurm.conf changed; restarting the Slurm daemons"
        stop_slurm
    fi
    mv -f -- "$CONF.new" "$CONF"
    start_munged
    start_slurm
    wait_for_node
    echo "export SLURM_CONF=$CONF" >"$DIR/env.sh"
    say "node $NODE is up: $(SLURM_CONF=$CONF sinfo -h -n "$NODE" -o '%T, %c CPUs, %m MiB') (daemons" \
        "ready in $(elapsed "$t1"), 'up' took $(elapsed "$t0")); job-completion log: $JOBCOMP"
    echo "export SLURM_CONF=$CONF"
}

cmd_install() {
    need_root install
    trap '[[ $MADE_POLICY -eq 1 ]] && rm -f /usr/sbin/policy-rc.d' EXIT
    claim_dir
    install_packages
}

cmd_down() {
    local pids i=0 left
    need_root down
    if [[ ! -e $DIR/$MARKER ]]; then
        say "no cluster of this script in $DIR; nothing to stop"
        return 0
    fi
    if running_pid "$CTLD_PID" slurmctld >/dev/null; then
        pids=$(SLURM_CONF=$CONF squeue -h -o %F 2>/dev/null | sort -u | tr '\n' ' ') || pids=""
        if [[ -n ${pids// /} ]]; then
            say "cancelling jobs $pids"
            # shellcheck disable=SC2086  # one word per job id
            SLURM_CONF=$CONF scancel $pids 2>/dev/null || true
            # Only a live slurmd ends the jobs' processes and reports them done; without it
            # they stay `completing` and are killed below instead.
            running_pid "$SLURMD_PID" slurmd >/dev/null || i=$((CANCEL_WAIT * 2))
            for (( ; i < CANCEL_WAIT * 2; i++)); do
                left=$(SLURM_CONF=$CONF squeue -h -t running,completing,configuring -o %i 2>/dev/null) ||
                    break
                [[ -z $left ]] && break
                sleep 0.5
            done
        fi
    fi
    stop_slurm
    stop_pidfile "$MUNGE_PID" munged
    rm -f -- "$MUNGE_SOCKET" "$MUNGE_SOCKET.lock"
    # What outlived its daemon: a step daemon or job of a crashed slurmd, a daemon whose
    # pid file was lost.
    mapfile -t pids < <(leftover_pids)
    if [[ ${#pids[@]} -gt 0 ]]; then
        say "killing ${#pids[@]} leftover processes of this cluster: ${pids[*]}"
        kill -KILL "${pids[@]}" 2>/dev/null || true
        sleep 0.5
    fi
    mapfile -t pids < <(leftover_pids)
    if [[ ${#pids[@]} -gt 0 ]]; then
        die 1 "processes of the cluster in $DIR are still running: ${pids[*]}"
    fi
    say "stopped; $DIR is kept (logs, state, jobcomp.log); remove it to start afresh"
}

cmd_status() {
    local ok=0 name file pid
    if [[ ! -e $DIR/$MARKER ]]; then
        say "no cluster of this script in $DIR"
        return 1
    fi
    for name in munged slurmctld slurmd; do
        case $name in
        munged) file=$MUNGE_PID ;;
        slurmctld) file=$CTLD_PID ;;
        slurmd) file=$SLURMD_PID ;;
        esac
        if pid=$(running_pid "$file" "$name"); then
            echo "$name: running (pid $pid)"
        else
            echo "$name: not running"
            ok=1
        fi
    done
    echo "SLURM_CONF=$CONF"
    if running_pid "$CTLD_PID" slurmctld >/dev/null; then
        SLURM_CONF=$CONF sinfo || ok=1
        SLURM_CONF=$CONF squeue || ok=1
    fi
    return "$ok"
}

main() {
    local cmd=${1:-help}
    [[ $# -gt 0 ]] && shift
    [[ $# -le 1 ]] || die 2 "too many arguments; usage: $0 up|down|status|install [DIR]"
    case $cmd in
    up | down | status | install)
        set_paths "${1:-}"
        "cmd_$cmd"
        ;;
    help | -h | --help) usage ;;
    *)
        die 2 "unknown command '$cmd'; usage: $0 up|down|status|install [DIR] (or: $0 help)"
        ;;
    esac
}

main "$@"
