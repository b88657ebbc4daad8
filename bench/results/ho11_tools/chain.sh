#!/bin/bash
# after the design loop: build the designed specs (harness, one per invocation), then the first
# change of each refusal (run_fixes.py); nothing starts after 11:38 UTC, every run ends by 11:45
cd /work/wt/ho11
while ! grep -q '^done' /tmp/ho11/design/times.txt; do sleep 10; done
END=$(date -u -d 'today 11:45' +%s)
left() { echo $(( END - $(date -u +%s) )); }
for n in $(grep ' rc=0 ' /tmp/ho11/design/times.txt | cut -d' ' -f1); do
  t=$(left); [ $t -lt 420 ] && { echo "stop before build $n: $t s left" >> /tmp/ho11/chain.log; [ $t -lt 120 ] && exit 0; }
  [ $t -gt 420 ] && t=420
  echo "$(date -u +%T) build $n timeout $t" >> /tmp/ho11/chain.log
  nice -n 10 python bench/spec_heldout.py --configs /tmp/ho30/configs --keep /tmp/ho11/b --code $PWD --jobs 1 --timeout $t --only $n >> /tmp/ho11/chain.build.out 2>&1
done
for n in $(grep ' rc=2 ' /tmp/ho11/design/times.txt | cut -d' ' -f1); do
  t=$(left); [ $t -lt 120 ] && { echo "stop before fix $n" >> /tmp/ho11/chain.log; exit 0; }
  [ $t -gt 420 ] && t=420
  echo "$(date -u +%T) fix $n timeout $t" >> /tmp/ho11/chain.log
  nice -n 10 python /tmp/ho11/tools/run_fixes.py /tmp/ho11/f $n $t >> /tmp/ho11/chain.fix.out 2>&1
done
echo "$(date -u +%T) chain done" >> /tmp/ho11/chain.log
