from glob import glob

from setuptools import find_packages, setup

package_name = 'robotica_sim'

setup(
    name=package_name,
    version='0.1.0',
    packages=find_packages(exclude=['test', 'test.*']),
    data_files=[
        ('share/ament_index/resource_index/packages', ['resource/' + package_name]),
        ('share/' + package_name, ['package.xml']),
        ('share/' + package_name + '/scenarios', glob('scenarios/*.yaml')),
        ('share/' + package_name + '/rubrics', glob('rubrics/*.yaml')),
        ('share/' + package_name + '/templates', glob('templates/*')),
    ],
    install_requires=['setuptools'],
    zip_safe=True,
    maintainer='robotica developers',
    maintainer_email='robotica@example.com',
    description=(
        'Simulation side of robotica: integrator simulators, sensor emulators, odometry, '
        'the bag recorder, scenarios and the robotica command.'),
    license='Apache-2.0',
    tests_require=['pytest'],
    entry_points={
        'console_scripts': [
            'simulator = robotica_sim.nodes.simulator:main',
            'arm_simulator = robotica_sim.nodes.arm_simulator:main',
            'encoder_emulator = robotica_sim.nodes.encoder_emulator:main',
            'gyro_emulator = robotica_sim.nodes.gyro_emulator:main',
            'compass_emulator = robotica_sim.nodes.compass_emulator:main',
            'gps_emulator = robotica_sim.nodes.gps_emulator:main',
            'sonar_emulator = robotica_sim.nodes.sonar_emulator:main',
            'infrared_emulator = robotica_sim.nodes.infrared_emulator:main',
            'laser_emulator = robotica_sim.nodes.laser_emulator:main',
            'ft_sensor_emulator = robotica_sim.nodes.ft_sensor_emulator:main',
            'odometry = robotica_sim.nodes.odometry:main',
            'recorder = robotica_sim.nodes.recorder:main',
            'view_relay = robotica_sim.nodes.view_relay:main',
            'markers = robotica_sim.nodes.markers:main',
            'world_publisher = robotica_sim.nodes.world_publisher:main',
            'robotica = robotica_sim.cli.main:main',
        ],
    },
)
