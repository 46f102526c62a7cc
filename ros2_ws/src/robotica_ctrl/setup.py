from setuptools import find_packages, setup

package_name = 'robotica_ctrl'

setup(
    name=package_name,
    version='0.1.0',
    packages=find_packages(exclude=['test', 'test.*']),
    data_files=[
        ('share/ament_index/resource_index/packages', ['resource/' + package_name]),
        ('share/' + package_name, ['package.xml']),
    ],
    install_requires=['setuptools'],
    zip_safe=True,
    maintainer='robotica developers',
    maintainer_email='robotica@example.com',
    description=(
        'Controllers of robotica: trajectories, joint controllers, mobile path trackers '
        'and planners, each a pure core with a thin ROS 2 node.'),
    license='Apache-2.0',
    tests_require=['pytest'],
    entry_points={
        'console_scripts': [
            'path_tracker = robotica_ctrl.nodes.path_tracker:main',
            'planner = robotica_ctrl.nodes.planner:main',
            'mapper = robotica_ctrl.nodes.mapper:main',
            'path_publisher = robotica_ctrl.nodes.path_publisher:main',
            'joint_controller = robotica_ctrl.nodes.joint_controller:main',
            'joint_trajectory_publisher = robotica_ctrl.nodes.joint_trajectory_publisher:main',
            'reactive_navigator = robotica_ctrl.nodes.reactive_navigator:main',
        ],
    },
)
