"""What a finished data-set job tells a person: the runs re-made, written, complete and failed.

:func:`job_outcome` turns a job's :class:`~aaria_pin.apps.dataset.job.DatasetReport` into the
lines ``aaria dataset`` prints (a Python caller gets the same words).
"""

from __future__ import annotations

from aaria_pin.apps.dataset.job import DatasetReport

__all__ = ["job_outcome"]


def job_outcome(report: DatasetReport, n_runs: int, resume: bool) -> tuple[str, list[str]]:
    """The report's text and its failures' lines.

    Args:
        report: what the job did
        n_runs: the runs of the data set
        resume: whether the job resumed a file (a complete file is then "nothing to do")

    Returns:
        The text (a line per run re-made, then the file's state) and one line per failed run
        followed by the list of them (empty when none failed).
    """
    text = "".join(f"run {run} was damaged; re-made\n" for run in report.remade)
    if resume and report.written == 0 and report.complete == n_runs and not report.failures:
        return text + f"{report.path}: already complete ({n_runs}/{n_runs} runs); nothing to do", []
    in_shards = f", {report.shards} shards" if report.shards else ""
    text += (f"wrote {report.path}: {report.complete}/{n_runs} runs complete "
             f"({report.written} in this job{in_shards}, {report.seconds:.1f} s)")  # fmt: skip
    failures = [f"run {run} failed: {message}" for run, message in sorted(report.failures.items())]
    return text, failures + ([f"failed runs: {sorted(report.failures)}"] if failures else [])
