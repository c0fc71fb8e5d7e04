"""The ROS 2 package (ament_python; colcon build, or pip install . into a Python environment with cv2.lidarsgm)."""
from glob import glob

from setuptools import setup

setup(
    name="lidarsgm_ros",
    version="0.1.0",
    packages=["lidarsgm_ros"],
    data_files=[
        ("share/ament_index/resource_index/packages", ["resource/lidarsgm_ros"]),
        ("share/lidarsgm_ros", ["package.xml"]),
        ("share/lidarsgm_ros/launch", glob("launch/*.launch.py")),
        ("share/lidarsgm_ros/config", glob("config/*.yaml") + glob("config/*.xml")),
    ],
    install_requires=["numpy"],
    extras_require={"bags": ["rosbags"]},
    description="Stereo-LiDAR fusion (cv2.lidarsgm) as a ROS 2 node and a rosbag2 command",
    license="Apache-2.0",
    entry_points={"console_scripts": [
        "lidarsgm_node = lidarsgm_ros.node:main",
        "lidarsgm_bag = lidarsgm_ros.bag:main",
        "lidarsgm_kitti_to_bag = lidarsgm_ros.kitti:main",
    ]},
)
