"""Launches lidarsgm_node as stereo_image_proc's disparity launch does: the node in a namespace, its topics
remappable, the parameters from config/lidarsgm.yaml and the arguments.

  ros2 launch lidarsgm_ros lidarsgm.launch.py namespace:=stereo params_file:=/path/kitti_best.yml \
      lidar_to_camera:="[...16 numbers...]" points:=/velodyne_points
"""
import os
from typing import List

from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node
from launch_ros.parameter_descriptions import ParameterValue


def generate_launch_description():
    config = os.path.join(get_package_share_directory("lidarsgm_ros"), "config", "lidarsgm.yaml")
    args = [
        DeclareLaunchArgument("namespace", default_value="", description="namespace of the inputs and outputs"),
        DeclareLaunchArgument("params_file", default_value="", description="matcher parameters (kitti_best.yml)"),
        DeclareLaunchArgument("lidar_to_camera", description="4x4 LiDAR -> left optical frame, row by row"),
        DeclareLaunchArgument("use_cuda", default_value="false"),
        DeclareLaunchArgument("approximate_sync", default_value="false"),
        DeclareLaunchArgument("points", default_value="points", description="the LiDAR's PointCloud2 topic"),
    ]
    node = Node(
        package="lidarsgm_ros", executable="lidarsgm_node", name="lidarsgm",
        namespace=LaunchConfiguration("namespace"), output="screen",
        parameters=[config, {
            "params_file": LaunchConfiguration("params_file"),
            "lidar_to_camera": ParameterValue(LaunchConfiguration("lidar_to_camera"), value_type=List[float]),
            "use_cuda": ParameterValue(LaunchConfiguration("use_cuda"), value_type=bool),
            "approximate_sync": ParameterValue(LaunchConfiguration("approximate_sync"), value_type=bool),
        }],
        remappings=[("points", LaunchConfiguration("points"))])
    return LaunchDescription(args + [node])
