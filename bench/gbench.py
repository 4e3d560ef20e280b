"""Running a Google Benchmark program and reading its medians: shared by the *_tradeoff.py scripts."""
import json
import subprocess


def run(bench, repetitions):
    """The program's JSON report, `repetitions` runs of every benchmark, aggregates only."""
    out = subprocess.run([bench, "--benchmark_format=json", f"--benchmark_repetitions={repetitions}",
                          "--benchmark_report_aggregates_only=true"], check=True, capture_output=True, text=True)
    return json.loads(out.stdout)


def medians(data):
    """run_name -> the median row of each benchmark."""
    return {b["run_name"]: b for b in data["benchmarks"] if b.get("aggregate_name") == "median"}
