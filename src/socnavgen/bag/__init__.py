"""ROS 2 bags (rosbag2: MCAP or sqlite3) of HuNavSim runs, through the pure-Python `rosbags` library and
HuNavSim's real hunav_msgs definitions (msgs/): `write_bag` records a simulated episode so that Foxglove
and RViz show it; `bag_to_trace` turns a recording (ours or Gazebo's) into a Trace that the verifier and the
metrics judge like any simulation."""

from socnavgen.bag.reader import BagError, ReadTopics, read_recording
from socnavgen.bag.to_trace import BagReadOptions, BagTrace, bag_to_trace, recording_to_trace
from socnavgen.bag.writer import BagWriteOptions, Topics, write_bag

__all__ = ["BagError", "BagReadOptions", "BagTrace", "BagWriteOptions", "ReadTopics", "Topics", "bag_to_trace",
           "read_recording", "recording_to_trace", "write_bag"]
