#include "task/picker_localization.hpp"

#include <array>

#include "task/transition_table.hpp"

namespace fleet::task {

namespace {

using S = PickerLocalizationState;
using E = PickerLocalizationEvent;
using T = PickerLocalizationTransition;

// [Picker thesis, section 5.3.3.1.1, Fig. 5.3]; the walks follow Figs. 5.4-5.7.
constexpr std::array kTable{
    T{S::kStart, E::kReady, S::kWaitForCommand, 1},
    T{S::kWaitForCommand, E::kScanBothRgbRequested, S::kScanBothRgb, 2},
    T{S::kWaitForCommand, E::kScanRearRgbRequested, S::kScanRearRgb, 3},
    T{S::kWaitForCommand, E::kScanFrontRgbRequested, S::kScanFrontRgb, 4},
    T{S::kWaitForCommand, E::kScanLeftDepthRequested, S::kScanLeftDepth, 5},
    T{S::kWaitForCommand, E::kScanRightDepthRequested, S::kScanRightDepth, 9},
    // Both RGB cameras.
    T{S::kScanBothRgb, E::kScanDone, S::kEvaluateBothRgb, 7},
    T{S::kEvaluateBothRgb, E::kQuickScanMissed, S::kScanBothRgb, 6},
    T{S::kEvaluateBothRgb, E::kStepScanMissed, S::kReportNoMarker, 8},
    T{S::kEvaluateBothRgb, E::kMarkerSeen, S::kExtractMarker, 12},
    // Front RGB camera.
    T{S::kScanFrontRgb, E::kScanDone, S::kEvaluateFrontRgb, 10},
    T{S::kEvaluateFrontRgb, E::kQuickScanMissed, S::kScanFrontRgb, 15},
    T{S::kEvaluateFrontRgb, E::kStepScanMissed, S::kReportNoMarker, 37},
    T{S::kEvaluateFrontRgb, E::kMarkerSeen, S::kExtractMarker, 11},
    // Rear RGB camera.
    T{S::kScanRearRgb, E::kScanDone, S::kEvaluateRearRgb, 14},
    T{S::kEvaluateRearRgb, E::kQuickScanMissed, S::kScanRearRgb, 16},
    T{S::kEvaluateRearRgb, E::kStepScanMissed, S::kReportNoMarker, 22},
    T{S::kEvaluateRearRgb, E::kMarkerSeen, S::kExtractMarker, 13},
    // Right depth camera.
    T{S::kScanRightDepth, E::kScanDone, S::kEvaluateRightDepth, 19},
    T{S::kEvaluateRightDepth, E::kQuickScanMissed, S::kScanRightDepth, 20},
    T{S::kEvaluateRightDepth, E::kStepScanMissed, S::kReportNoMarker, 36},
    T{S::kEvaluateRightDepth, E::kMarkerSeen, S::kExtractMarker, 26},
    // Left depth camera.
    T{S::kScanLeftDepth, E::kScanDone, S::kEvaluateLeftDepth, 18},
    T{S::kEvaluateLeftDepth, E::kQuickScanMissed, S::kScanLeftDepth, 17},
    T{S::kEvaluateLeftDepth, E::kStepScanMissed, S::kReportNoMarker, 35},
    T{S::kEvaluateLeftDepth, E::kMarkerSeen, S::kExtractMarker, 21},
    // The marker's class and ID.
    T{S::kExtractMarker, E::kRackMarkerSeen, S::kCheckRackId, 23},
    T{S::kExtractMarker, E::kBoxMarkerSeen, S::kCheckBoxId, 24},
    T{S::kExtractMarker, E::kPalletMarkerSeen, S::kCheckPalletId, 25},
    T{S::kCheckRackId, E::kIdSought, S::kPublishMarker, 27},
    T{S::kCheckBoxId, E::kIdSought, S::kPublishMarker, 28},
    T{S::kCheckPalletId, E::kIdSought, S::kPublishMarker, 29},
    T{S::kCheckBoxId, E::kWrongBoxIdLeftCamera, S::kScanLeftDepth, 30},
    T{S::kCheckBoxId, E::kWrongBoxIdRightCamera, S::kScanRightDepth, 32},
    // The net names no camera for a wrong rack or pallet ID: both RGB cameras see those markers.
    T{S::kCheckRackId, E::kWrongId, S::kScanBothRgb, 33},
    T{S::kCheckPalletId, E::kWrongId, S::kScanBothRgb, 34},
    // The same wrong marker would be seen forever: after the rescan it counts as none found.
    T{S::kCheckRackId, E::kWrongIdAgain, S::kReportNoMarker, 0},
    T{S::kCheckPalletId, E::kWrongIdAgain, S::kReportNoMarker, 0},
    T{S::kCheckBoxId, E::kWrongIdAgain, S::kReportNoMarker, 0},
    T{S::kPublishMarker, E::kPublished, S::kWaitForCommand, 31},
    T{S::kReportNoMarker, E::kMessageSent, S::kWaitForCommand, 38},
};

}  // namespace

const char* to_string(PickerLocalizationState state) {
  switch (state) {
    case S::kStart:
      return "START";
    case S::kWaitForCommand:
      return "WAIT_FOR_COMMAND";
    case S::kScanBothRgb:
      return "SCAN_BOTH_RGB";
    case S::kEvaluateBothRgb:
      return "EVALUATE_BOTH_RGB";
    case S::kScanFrontRgb:
      return "SCAN_FRONT_RGB";
    case S::kEvaluateFrontRgb:
      return "EVALUATE_FRONT_RGB";
    case S::kScanRearRgb:
      return "SCAN_REAR_RGB";
    case S::kEvaluateRearRgb:
      return "EVALUATE_REAR_RGB";
    case S::kScanRightDepth:
      return "SCAN_RIGHT_DEPTH";
    case S::kEvaluateRightDepth:
      return "EVALUATE_RIGHT_DEPTH";
    case S::kScanLeftDepth:
      return "SCAN_LEFT_DEPTH";
    case S::kEvaluateLeftDepth:
      return "EVALUATE_LEFT_DEPTH";
    case S::kExtractMarker:
      return "EXTRACT_MARKER";
    case S::kCheckPalletId:
      return "CHECK_PALLET_ID";
    case S::kCheckRackId:
      return "CHECK_RACK_ID";
    case S::kCheckBoxId:
      return "CHECK_BOX_ID";
    case S::kPublishMarker:
      return "PUBLISH_MARKER";
    case S::kReportNoMarker:
      return "REPORT_NO_MARKER";
  }
  return "?";
}

const char* to_string(PickerLocalizationEvent event) {
  switch (event) {
    case E::kReady:
      return "ready";
    case E::kScanBothRgbRequested:
      return "scan both rgb requested";
    case E::kScanRearRgbRequested:
      return "scan rear rgb requested";
    case E::kScanFrontRgbRequested:
      return "scan front rgb requested";
    case E::kScanLeftDepthRequested:
      return "scan left depth requested";
    case E::kScanRightDepthRequested:
      return "scan right depth requested";
    case E::kScanDone:
      return "scan done";
    case E::kMarkerSeen:
      return "marker seen";
    case E::kQuickScanMissed:
      return "quick scan missed";
    case E::kStepScanMissed:
      return "step scan missed";
    case E::kPalletMarkerSeen:
      return "pallet marker seen";
    case E::kRackMarkerSeen:
      return "rack marker seen";
    case E::kBoxMarkerSeen:
      return "box marker seen";
    case E::kIdSought:
      return "id sought";
    case E::kWrongId:
      return "wrong id";
    case E::kWrongBoxIdLeftCamera:
      return "wrong box id, left camera";
    case E::kWrongBoxIdRightCamera:
      return "wrong box id, right camera";
    case E::kWrongIdAgain:
      return "wrong id again";
    case E::kPublished:
      return "published";
    case E::kMessageSent:
      return "message sent";
  }
  return "?";
}

std::span<const PickerLocalizationTransition> picker_localization_table() {
  return kTable;
}

std::optional<PickerLocalizationState> next_picker_localization_state(PickerLocalizationState from,
                                                                      PickerLocalizationEvent event) {
  return next_state(kTable, from, event);
}

}  // namespace fleet::task
