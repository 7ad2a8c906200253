#!/bin/sh
# Stand-in for a scheduler's submit command (no scheduler needed): records the job's name and
# resources, then starts the job script Snakemake appends as a local background process (a copy
# of the script and its output stay beside the record) and prints its process id as the job id.
#   local_submit.sh <record file> <name> <mem_mb> <runtime> <job script>
record="$1"
name="$2"
mem_mb="$3"
runtime="$4"
jobscript="$5"
echo "$name $mem_mb $runtime $jobscript" >> "$record"
kept="$(dirname "$record")/$(basename "$jobscript")"
cp "$jobscript" "$kept"
nohup sh "$jobscript" > "$kept.out" 2>&1 &
echo $!
