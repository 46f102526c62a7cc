from setuptools import find_packages, setup

package_name = 'robotica_kin'

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
        'Kinematic and dynamic models of robotica: transforms, DH models, mobile-robot '
        'models, odometry maths (pure Python/NumPy, Pinocchio for dynamics).'),
    license='Apache-2.0',
    tests_require=['pytest'],
    entry_points={
        'console_scripts': [
            'fk_node = robotica_kin.nodes.fk_node:main',
            'ik_server = robotica_kin.nodes.ik_server:main',
            'state_publisher = robotica_kin.nodes.state_publisher:main',
        ],
    },
)
