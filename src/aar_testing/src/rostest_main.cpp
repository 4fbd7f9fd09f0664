// The main of every rostest executable in this package (aar_ros_common::RunRostests).
#include <aar_ros_common/rostest_main.h>

int main(int argc, char** argv) { return aar_ros_common::RunRostests(argc, argv, "aar_rostest"); }
