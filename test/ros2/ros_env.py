"""What every ROS 2 test of the package sets before rclpy is imported: the package on the path, discovery on this
machine only, a domain of its own (LIDARSGM_ROS_DOMAIN_ID, else a random one), and the package's Fast DDS profile
for this process, which publishes megabyte messages as a driver would (on the defaults most of them are lost)."""
import os
import random
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
PACKAGE = os.path.join(HERE, "..", "..", "ros2", "lidarsgm_ros")
sys.path.insert(0, PACKAGE)
os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
os.environ["FASTDDS_DEFAULT_PROFILES_FILE"] = os.path.join(PACKAGE, "config", "fastdds_large_data.xml")
os.environ["ROS_DOMAIN_ID"] = os.environ.get("LIDARSGM_ROS_DOMAIN_ID", str(random.randint(100, 200)))
