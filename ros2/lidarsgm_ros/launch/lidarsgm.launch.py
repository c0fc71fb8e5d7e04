"""Launches lidarsgm_node as stereo_image_proc's disparity launch does: the node in a namespace, its topics
remappable, the parameters from config/lidarsgm.yaml and the arguments. The LiDAR-to-camera transform comes from tf
(the robot's /tf_static, from its URDF), unless lidar_to_camera gives it.

  ros2 launch lidarsgm_ros lidarsgm.launch.py namespace:=stereo params_file:=/path/kitti_best.yml \
      points:=/velodyne_points
  ros2 launch lidarsgm_ros lidarsgm.launch.py ... lidar_to_camera:="[...16 numbers...]"   # tf overridden

Megabyte messages between processes: the node runs with the package's Fast DDS profile (config/
fastdds_large_data.xml: 32 MiB shared-memory segments, 4096 messages a port, 4 MB UDP buffers) unless the
environment has FASTDDS_DEFAULT_PROFILES_FILE or FASTDDS_BUILTIN_TRANSPORTS, or fastdds_profile:= names another
file. The camera and LiDAR drivers that publish to it need the profile too (a message is lost in the SENDER's 512 KiB
default segment: 0 of 30 KITTI sets at 5 Hz without it, 30 of 30 with it, tools/ros2_stream.py probe): launch them
after SetEnvironmentVariable("FASTDDS_DEFAULT_PROFILES_FILE", <share>/lidarsgm_ros/config/fastdds_large_data.xml),
or export it in their shell.
"""
import os

from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, OpaqueFunction
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node
from launch_ros.parameter_descriptions import ParameterValue


def _node(context):
    config = os.path.join(get_package_share_directory("lidarsgm_ros"), "config", "lidarsgm.yaml")
    params = {
        "params_file": LaunchConfiguration("params_file"),
        "use_cuda": ParameterValue(LaunchConfiguration("use_cuda"), value_type=bool),
        "approximate_sync": ParameterValue(LaunchConfiguration("approximate_sync"), value_type=bool),
    }
    # The drivers' side of the same profile is the user's (above); the node's own, unless the environment decides.
    profile = LaunchConfiguration("fastdds_profile").perform(context).strip() or os.path.join(
        get_package_share_directory("lidarsgm_ros"), "config", "fastdds_large_data.xml")
    env, environ = {}, getattr(context, "environment", os.environ)  # SetEnvironmentVariable's changes included
    if not any(k in environ for k in ("FASTDDS_DEFAULT_PROFILES_FILE", "FASTDDS_BUILTIN_TRANSPORTS")) \
            or LaunchConfiguration("fastdds_profile").perform(context).strip():
        env["FASTDDS_DEFAULT_PROFILES_FILE"] = profile
    given = LaunchConfiguration("lidar_to_camera").perform(context).strip()
    if given:
        params["lidar_to_camera"] = [float(v) for v in given.strip("[]").replace(",", " ").split()]
    return [Node(package="lidarsgm_ros", executable="lidarsgm_node", name="lidarsgm",
                 namespace=LaunchConfiguration("namespace"), output="screen", parameters=[config, params],
                 remappings=[("points", LaunchConfiguration("points"))], additional_env=env)]


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument("namespace", default_value="", description="namespace of the inputs and outputs"),
        DeclareLaunchArgument("params_file", default_value="", description="matcher parameters (kitti_best.yml)"),
        DeclareLaunchArgument("lidar_to_camera", default_value="",
                              description="4x4 LiDAR -> left optical frame, row by row; empty: from tf"),
        DeclareLaunchArgument("use_cuda", default_value="false"),
        DeclareLaunchArgument("approximate_sync", default_value="false"),
        DeclareLaunchArgument("points", default_value="points", description="the LiDAR's PointCloud2 topic"),
        DeclareLaunchArgument("fastdds_profile", default_value="",
                              description="Fast DDS XML profile for the node; empty: the package's "
                              "fastdds_large_data.xml unless FASTDDS_DEFAULT_PROFILES_FILE or "
                              "FASTDDS_BUILTIN_TRANSPORTS is set"),
        OpaqueFunction(function=_node),
    ])
