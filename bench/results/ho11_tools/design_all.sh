#!/bin/bash
# design stage of every held-out config on /work/wt/ho11 (current main d533b40)
export PYTHONPATH=/work/wt/ho11
for f in /tmp/ho30/configs/g*.toml; do
  n=$(basename $f .toml)
  s=$(date +%s.%N)
  timeout -s KILL 420 nice -n 10 python -m springcad design $f --out /tmp/ho11/design/$n --overwrite > /tmp/ho11/design/$n.log 2>&1
  rc=$?
  e=$(date +%s.%N)
  echo "$n rc=$rc s=$(echo "$e - $s" | bc) load=$(cut -d' ' -f1 /proc/loadavg)" >> /tmp/ho11/design/times.txt
done
echo done >> /tmp/ho11/design/times.txt
