"""Benchmark tasks: a fixed data set, splits by run, a target, a metric and a scorer of files.

A task (:class:`~.task.BenchTask`, registered in :data:`~.registry.TASKS`) names its data set
spec (:class:`~.task.TaskSpec`), the fields a model reads (``inputs``) and the one it predicts
(``target``), and scores predictions of the test runs (:mod:`.predictions`: an NPZ file, one
array ``run_<k>`` per test run, the target's shape). :func:`~.make.make_task` writes a task's
data set and its card (:mod:`.card`); :func:`~.scoring.score_task` scores a predictions file;
:mod:`.baselines` writes the floors (and task 1's classical identification).
"""
