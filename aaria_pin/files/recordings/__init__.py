"""Recordings in and out: ROS 1 bags, ROS 2 bags (sqlite3, MCAP) and MCAP files.

:func:`~aaria_pin.files.recordings.bag_write.write_bag` writes a
:class:`~aaria_pin.core.recording.RecordedRun` as ``sensor_msgs/Imu``,
``sensor_msgs/JointState`` and ``geometry_msgs/WrenchStamped`` messages;
:func:`~aaria_pin.files.recordings.bag_read.read_bag` reads them back. Both go through
``rosbags`` (no ROS install; the optional extra ``ros``), imported inside them only.
"""
