# CMAKE_PROJECT_INCLUDE for the ROS 2 overlay build (tools/ros_overlay.py).
#
# An interface package (package.xml in group rosidl_interface_packages) generates and
# compiles code for every rosidl generator found: C, Python, type descriptions, and the C++
# ones (rosidl_generator_cpp headers, rosidl_typesupport_cpp and its fastrtps/introspection
# implementations). Nothing here uses C++ message code (rclpy needs the C code and its C
# typesupports only), and the C++ typesupports are most of the compile time. So: find the
# generators now, as the package's own find_package(rosidl_default_generators) would (that
# one then returns at once: each config file is read once), and unregister the C++ ones.
if(EXISTS "${PROJECT_SOURCE_DIR}/package.xml")
  file(READ "${PROJECT_SOURCE_DIR}/package.xml" _sar_package_xml)
  if(_sar_package_xml MATCHES "<member_of_group>rosidl_interface_packages</member_of_group>")
    find_package(rosidl_default_generators REQUIRED)
    foreach(_sar_generator rosidl_generator_cpp rosidl_typesupport_cpp
        rosidl_typesupport_fastrtps_cpp rosidl_typesupport_introspection_cpp)
      list(FILTER AMENT_EXTENSIONS_rosidl_generate_idl_interfaces
        EXCLUDE REGEX "^${_sar_generator}:")
    endforeach()
    message(STATUS "sar_framework overlay: C++ interface generators skipped; generating "
      "${AMENT_EXTENSIONS_rosidl_generate_idl_interfaces}")
  endif()
endif()
