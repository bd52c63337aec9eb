"""Exports of a robot to other simulators: MuJoCo's MJCF (written, compiled, a run replayed).

- :mod:`~aaria_pin.core.export.mjcf_bodies`: the ``<body>`` tree of a parsed URDF (inertials,
  joints, shapes, meshes, IMU sites);
- :mod:`~aaria_pin.core.export.mjcf_emit`: the whole MJCF document (:func:`emit_mjcf`), its
  compilation (:func:`load_mjcf`) and MuJoCo's inertia balancing on request;
- :mod:`~aaria_pin.core.export.mjcf_replay`: a run's motion set in MuJoCo, its sensors and
  inverse dynamics read back (:func:`replay_motion`).

The export knows no robot kind: it takes a URDF, IMU mounts and a base motion; what a run
record of a given kind supplies is read in :mod:`aaria_pin.apps.record_model`.
"""
