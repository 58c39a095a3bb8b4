#include "io/bag/ros2_schemas.hpp"

#include <initializer_list>

namespace dammloam::io {
namespace {

const char* const kHeader = "builtin_interfaces/Time stamp\nstring frame_id\n";
const char* const kTime = "int32 sec\nuint32 nanosec\n";
const char* const kPoint = "float64 x\nfloat64 y\nfloat64 z\n";
const char* const kQuaternion = "float64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1\n";
const char* const kPose = "Point position\nQuaternion orientation\n";

struct Part {
  const char* name;
  const char* text;
};

// Dependencies are named "pkg/Type" after MSG:, as rosbag2 writes them and as Foxglove's parser
// (@foxglove/rosmsg) looks up fully qualified references such as "std_msgs/Header": with
// "pkg/msg/Type" it finds no definition and refuses the whole schema (tests/bridge showed it).
std::string Join(const char* top, std::initializer_list<Part> dependencies) {
  std::string out = top;
  for (const Part& part : dependencies) {
    std::string name = part.name;
    if (const std::size_t msg = name.find("/msg/"); msg != std::string::npos) name.erase(msg, 4);
    out += std::string(80, '=') + "\nMSG: " + name + "\n" + part.text;
  }
  return out;
}

}  // namespace

const std::string& OdometrySchema() {
  static const std::string schema = Join(
      "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/PoseWithCovariance pose\n"
      "geometry_msgs/TwistWithCovariance twist\n",
      {{"std_msgs/msg/Header", kHeader},
       {"builtin_interfaces/msg/Time", kTime},
       {"geometry_msgs/msg/PoseWithCovariance", "Pose pose\nfloat64[36] covariance\n"},
       {"geometry_msgs/msg/Pose", kPose},
       {"geometry_msgs/msg/Point", kPoint},
       {"geometry_msgs/msg/Quaternion", kQuaternion},
       {"geometry_msgs/msg/TwistWithCovariance", "Twist twist\nfloat64[36] covariance\n"},
       {"geometry_msgs/msg/Twist", "Vector3 linear\nVector3 angular\n"},
       {"geometry_msgs/msg/Vector3", kPoint}});
  return schema;
}

const std::string& TfMessageSchema() {
  static const std::string schema = Join(
      "geometry_msgs/TransformStamped[] transforms\n",
      {{"geometry_msgs/msg/TransformStamped",
        "std_msgs/Header header\nstring child_frame_id\nTransform transform\n"},
       {"std_msgs/msg/Header", kHeader},
       {"builtin_interfaces/msg/Time", kTime},
       {"geometry_msgs/msg/Transform", "Vector3 translation\nQuaternion rotation\n"},
       {"geometry_msgs/msg/Vector3", kPoint},
       {"geometry_msgs/msg/Quaternion", kQuaternion}});
  return schema;
}

const std::string& PointCloud2Schema() {
  static const std::string schema = Join(
      "std_msgs/Header header\nuint32 height\nuint32 width\nPointField[] fields\n"
      "bool is_bigendian\nuint32 point_step\nuint32 row_step\nuint8[] data\nbool is_dense\n",
      {{"std_msgs/msg/Header", kHeader},
       {"builtin_interfaces/msg/Time", kTime},
       {"sensor_msgs/msg/PointField",
        "uint8 INT8=1\nuint8 UINT8=2\nuint8 INT16=3\nuint8 UINT16=4\nuint8 INT32=5\n"
        "uint8 UINT32=6\nuint8 FLOAT32=7\nuint8 FLOAT64=8\n"
        "string name\nuint32 offset\nuint8 datatype\nuint32 count\n"}});
  return schema;
}

const std::string& StringSchema() {
  static const std::string schema = "string data\n";
  return schema;
}

const std::string& MarkerArraySchema() {
  static const std::string schema = Join(
      "Marker[] markers\n",
      {{"visualization_msgs/msg/Marker",
        "int32 ARROW=0\nint32 CUBE=1\nint32 SPHERE=2\nint32 CYLINDER=3\nint32 LINE_STRIP=4\n"
        "int32 LINE_LIST=5\nint32 CUBE_LIST=6\nint32 SPHERE_LIST=7\nint32 POINTS=8\n"
        "int32 TEXT_VIEW_FACING=9\nint32 MESH_RESOURCE=10\nint32 TRIANGLE_LIST=11\n"
        "int32 ADD=0\nint32 MODIFY=0\nint32 DELETE=2\nint32 DELETEALL=3\n"
        "std_msgs/Header header\nstring ns\nint32 id\nint32 type\nint32 action\n"
        "geometry_msgs/Pose pose\ngeometry_msgs/Vector3 scale\nstd_msgs/ColorRGBA color\n"
        "builtin_interfaces/Duration lifetime\nbool frame_locked\ngeometry_msgs/Point[] points\n"
        "std_msgs/ColorRGBA[] colors\nstring texture_resource\nsensor_msgs/CompressedImage texture\n"
        "UVCoordinate[] uv_coordinates\nstring text\nstring mesh_resource\nMeshFile mesh_file\n"
        "bool mesh_use_embedded_materials\n"},
       {"std_msgs/msg/Header", kHeader},
       {"builtin_interfaces/msg/Time", kTime},
       {"geometry_msgs/msg/Pose", kPose},
       {"geometry_msgs/msg/Point", kPoint},
       {"geometry_msgs/msg/Quaternion", kQuaternion},
       {"geometry_msgs/msg/Vector3", kPoint},
       {"std_msgs/msg/ColorRGBA", "float32 r\nfloat32 g\nfloat32 b\nfloat32 a\n"},
       {"builtin_interfaces/msg/Duration", kTime},
       {"sensor_msgs/msg/CompressedImage", "std_msgs/Header header\nstring format\nuint8[] data\n"},
       {"visualization_msgs/msg/UVCoordinate", "float32 u\nfloat32 v\n"},
       {"visualization_msgs/msg/MeshFile", "string filename\nuint8[] data\n"}});
  return schema;
}

}  // namespace dammloam::io
