#pragma once
// MRPT rawlogs (.rawlog, plain or gzip), read through MRPT's own library
// (mrpt-obs, mrpt-serialization): the serialized objects one after the other,
// as CRawlog::saveToRawLogFile and rawlog-grabber write them, in either form:
//  - observations only: CObservation objects;
//  - actions-observations: CActionCollection, CSensoryFrame, CActionCollection, ...
// (a whole CRawlog object saved as one object is read too). Used:
//   CObservationRange        sonar: one sensor per (sensorLabel, sensorID), placed at the
//                            measurement's sensorPose, cone sensorConeApperture, ranges
//                            [minSensorDistance, maxSensorDistance]
//   CObservation2DRangeScan  a laser per sensorLabel: n beams (n from its first scan) at
//                            sensorPose, beam i at getScanAngle(i), max range maxRange;
//                            invalid ranges are no echo
//   CObservationOdometry     the odometry pose (one record each)
//   CActionRobotMovement2D   an odometry increment (the mean of poseChange), composed from
//                            the origin
// Records: one per odometry (observation or action); the readings of each range
// observation as a record at the latest odometry pose (readings before any
// odometry in an observations-only rawlog are skipped and counted; an
// actions-observations rawlog starts at the origin). Times: the observations'
// timestamps (seconds since 1970). Other classes (images, IMU, ...) are skipped
// and counted by class name.
// Robot: the sensors found in a first pass at opening, lasers then sonars,
// each sorted by label (and ID); named after a built-in robot it matches
// (within 1e-6), else mrpt-laser / mrpt-sonar / mrpt-laser-sonar.
// Bad input: a file MRPT cannot deserialize (not a rawlog, another MRPT
// version's classes, a truncated entry) is one InputError naming the file and
// the entry index.
#include <functional>
#include <memory>
#include <string>
#include <string_view>

#include "cogmap/io/log_reader.h"

namespace cogmap::io {

std::unique_ptr<LogReader> OpenMrptRawlog(const std::string& path, const LogOpenOptions& options = {});

// Writes records as an observations-only rawlog (gzip): per record a
// CObservationOdometry ("ODOMETRY") and, when it has readings, a
// CObservationRange ("SONAR": sensorID = sensor index, sensorPose = the
// sensor's pose) for sonar readings and a CObservation2DRangeScan ("LASER",
// "LASER2", ... per laser fan, invalid where a beam has no reading) for laser
// readings. Written all or nothing. Returns the number of records.
long WriteMrptRawlog(const std::string& path, const sensors::RobotDescription& robot,
                     const std::function<bool(sensors::LogRecord*)>& next);

// True when the first bytes (gzip or not) look like an MRPT serialized object:
// a class-name length byte with the high bit set followed by the class name.
bool LooksLikeMrptRawlog(const std::string& path);
// The same test on bytes already read (gunzipped): standard input's head.
bool LooksLikeMrptRawlogHead(std::string_view head);

}  // namespace cogmap::io
