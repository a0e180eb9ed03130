#!/usr/bin/env bash
# One segment of a chained ictus run, shared by the SLURM and PBS job scripts.
#
#   ictus-job.sh DECK [RESULTS]
#
# Runs ictus on DECK with a wall-time budget. If a checkpoint of an earlier segment exists it
# continues from it. When ictus stops at the budget (exit status 3, checkpoint written), the
# next segment is queued with $ICTUS_RESUBMIT, or, if that is empty, run right here.
# When the run completes, the checkpoint is removed, so running the job again starts afresh.
#
# Environment:
#   ICTUS          the ictus executable (default: build/bin/ictus of this repository)
#   ICTUS_LAUNCH   MPI launcher and its options, e.g. "srun" or "mpirun -np 4" (default: none)
#   ICTUS_WALL     seconds the time loop may run in this segment (required, > 0)
#   ICTUS_RESUBMIT command that queues the next segment (default: run it in this shell)
#   ICTUS_MAX_SEGMENTS  safety limit on the number of segments (default 100)
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
deck=${1:?usage: ictus-job.sh DECK [RESULTS]}
out=${2:-${deck%.*}.h5}
ckpt=${out%.h5}.chk.h5
ictus=${ICTUS:-$here/build/bin/ictus}
wall=${ICTUS_WALL:?set ICTUS_WALL to the seconds this segment may run}
max_segments=${ICTUS_MAX_SEGMENTS:-100}
read -r -a launch <<< "${ICTUS_LAUNCH:-}"

for ((segment = 1; segment <= max_segments; segment++)); do
  args=("$deck" -o "$out" --wall-time "$wall")
  if [[ -f "$ckpt" ]]; then
    args+=(--restart "$ckpt")
    echo "ictus-job: segment $segment continues from $ckpt"
  else
    echo "ictus-job: segment $segment starts $deck"
  fi
  status=0
  "${launch[@]}" "$ictus" "${args[@]}" || status=$?
  case $status in
    0)
      rm -f "$ckpt"
      echo "ictus-job: completed: $out"
      exit 0
      ;;
    3)
      if [[ -n "${ICTUS_RESUBMIT:-}" ]]; then
        echo "ictus-job: wall-time limit reached; queueing the next segment: $ICTUS_RESUBMIT"
        eval "$ICTUS_RESUBMIT"
        exit 0
      fi
      ;;
    *)
      echo "ictus-job: ictus failed with exit status $status; the chain stops" >&2
      exit "$status"
      ;;
  esac
done
echo "ictus-job: more than $max_segments segments; the chain stops" >&2
exit 4
