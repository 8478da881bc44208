"""ament_python package motoflex_ros: builds with colcon and installs with plain pip."""
from glob import glob

from setuptools import find_packages, setup

PACKAGE = "motoflex_ros"

# Pins of the ROS 2 Jazzy PyPI wheels (docs/virtual-bench.md, "Installing"). Kept out of
# install_requires: a colcon user gets rclpy and the messages from the ROS distribution instead.
ROS_JAZZY_WHEELS = [
    "ros-rclpy==7.1.6",
    "ros-rmw-fastrtps-cpp==8.4.3",
    "ros-std-msgs==5.3.6",
    "ros-geometry-msgs==5.3.6",
    "ros-sensor-msgs==5.3.6",
    "ros-diagnostic-msgs==5.3.6",
    "ros-visualization-msgs==5.3.6",
    "ros-rosgraph-msgs==2.0.3",
    "ros-builtin-interfaces==2.0.3",
    "ros-std-srvs==5.3.6",
    "ros-ament-index-python==1.8.1",
]

setup(
    name=PACKAGE,
    version="0.1.0",
    packages=find_packages(exclude=["test", "test.*"]),
    package_data={PACKAGE: ["config/*/*.yaml", "config/*/*.xml", "config/foxglove/*.json",
                            "config/components/mesh/*.yaml",
                            "config/components/mesh/*.msh"]},
    # the data is listed above; include_package_data would also take every file of the
    # manifest and warn "Package would be ignored" for each config/ folder (importable as a
    # namespace package motoflex_ros.config.*) in every colcon build
    include_package_data=False,
    data_files=[
        ("share/ament_index/resource_index/packages", ["resource/" + PACKAGE]),
        ("share/" + PACKAGE, ["package.xml"]),
        ("share/" + PACKAGE + "/config/components", glob("config/components/*.yaml")),
        ("share/" + PACKAGE + "/config/components/mesh", glob("config/components/mesh/*.*")),
        ("share/" + PACKAGE + "/config/vehicles", glob("config/vehicles/*.yaml")),
        ("share/" + PACKAGE + "/config/design", glob("config/design/*.yaml")),
        ("share/" + PACKAGE + "/config/protocols", glob("config/protocols/*.yaml")),
        ("share/" + PACKAGE + "/config/nodes", glob("config/nodes/*.yaml")),
        ("share/" + PACKAGE + "/config/dds", glob("config/dds/*.xml")),
        ("share/" + PACKAGE + "/config/foxglove", glob("config/foxglove/*.json")),
        ("share/" + PACKAGE + "/launch", glob("launch/*.launch.py")),
    ],
    python_requires=">=3.10",
    install_requires=[
        "numpy>=1.26",
        "scipy>=1.11",
        "PyYAML>=6.0",
        "statsmodels>=0.14",
        "matplotlib>=3.8",
        "tqdm>=4.66",
        # the engineer's own FE meshes (component: mesh): assembly and mesh formats
        "scikit-fem>=10",
        "meshio>=5.3",
        # motoflex study design: the Pareto front of mass against stability (NSGA-II)
        "pymoo>=0.6.1",
    ],
    extras_require={
        "ros": ROS_JAZZY_WHEELS,
        "record": ["mcap>=1.2", "mcap-ros2-support>=0.5", "rosbags>=0.10", "rerun-sdk>=0.41"],
        # pypardiso: MKL PARDISO for the Craig-Bampton of large meshes (issue 15; SuperLU when
        # absent); MKL ships wheels for x86-64 only
        "scale": ["dask[distributed]>=2024.1",
                  "pypardiso>=0.4.7; platform_machine == 'x86_64' or platform_machine == 'AMD64'"],
        # gmsh: a hollow tube meshed as an engineer's FE tool does (test_mesh_gmsh.py)
        # import-linter: the layer contract in pyproject.toml (test/test_layering.py)
        # pytest-xdist: ./test.sh runs the suite on two workers (test/conftest.py groups it)
        # playwright: drives the system chromium in the browser tests (test/headless_chromium.py;
        # its own browser downloads are not used)
        "test": ["pytest>=8", "ruff>=0.6", "import-linter>=2.16", "pytest-benchmark>=4",
                 "pillow>=10", "sympy>=1.12", "gmsh>=4.11", "pytest-xdist>=3.5", "mkdocs>=1.6",
                 "mkdocs-material>=9.5", "playwright>=1.50"],
    },
    zip_safe=True,
    maintainer="motoflex_ros developers",
    maintainer_email="motoflex@example.invalid",
    description="ROS 2 virtual test rig: lumped stiffness identification of motorcycle "
    "components and their effect on weave and wobble (Passigato et al. 2023).",
    license="Apache-2.0",
    entry_points={
        "console_scripts": [
            "motoflex = motoflex_ros.cli.main:main",
            # ROS nodes (ros2 run motoflex_ros NAME): see motoflex_ros/nodes/
            "sim_clock = motoflex_ros.nodes.sim_clock:main",
            "recorder = motoflex_ros.nodes.recorder:main",
            "bag_replay = motoflex_ros.nodes.bag_replay:main",
            "load_actuator = motoflex_ros.nodes.load_actuator:main",
            "component_simulator = motoflex_ros.nodes.component_simulator:main",
            "displacement_sensor = motoflex_ros.nodes.displacement_sensor:main",
            "identification = motoflex_ros.nodes.identification:main",
            "vehicle_simulator = motoflex_ros.nodes.vehicle_simulator:main",
        ],
    },
)
