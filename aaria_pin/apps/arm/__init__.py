"""The pick-and-place arm of the robotic-arm report: meshes, URDF, planar IK, hand, task.

Modules: :mod:`~aaria_pin.apps.arm.parts` (trimesh meshes, STL, mass properties),
:mod:`~aaria_pin.core.urdf` (URDF with mesh links), :mod:`~aaria_pin.apps.arm.dims` (dimensions,
where a gripped cylinder sits), :mod:`~aaria_pin.apps.arm.preset` (the ``pick-place-arm`` preset),
:mod:`~aaria_pin.apps.arm.ik` (two-link planar IK, no swing through the pillar),
:mod:`~aaria_pin.apps.arm.hand` (ZYZ hand angles), :mod:`~aaria_pin.apps.arm.task` (the
pick-and-place
trajectory), :mod:`~aaria_pin.apps.arm.payload` (payload torques, mount
wrench),
:mod:`~aaria_pin.apps.arm.run` (the run and its file), :mod:`~aaria_pin.apps.arm.report` (what
a run reports; the URDF folder),
:mod:`~aaria_pin.viz.arm_pictures` (PNG, GIF),
:mod:`~aaria_pin.viz._arm_source` (the viewers' plug-in; imports the viz package).
"""
