"""Mission exports: GPX, CSV, QGroundControl, MOOS and ROS files, and formation missions."""

__all__: list[str] = []
