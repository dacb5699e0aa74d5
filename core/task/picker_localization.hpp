#pragma once

#include <optional>
#include <span>

namespace fleet::task {

/// The picker's localization supervisor [Picker thesis, section 5.3.3.1.1, Fig. 5.3]: a server
/// that, on request from navigation or the arm, scans with one camera or a pair, extracts the
/// marker seen, checks its ID against the list the caller sent for the requested class (rack,
/// pallet, box), and publishes it, or reports that no marker was found. Each of the net's 18
/// places is one state. The two RGB (Axis) cameras see rack and pallet markers; the two depth
/// cameras on the pan-tilt units see box markers.
enum class PickerLocalizationState {
  kStart,               ///< P1.0
  kWaitForCommand,      ///< P2.0: waiting for a request (marker class and the IDs sought)
  kScanBothRgb,         ///< P3.0: front and rear RGB cameras scan together
  kEvaluateBothRgb,     ///< P3.1: was a marker detected?
  kScanFrontRgb,        ///< P4.0
  kEvaluateFrontRgb,    ///< P4.1
  kScanRearRgb,         ///< P5.0
  kEvaluateRearRgb,     ///< P5.1
  kScanRightDepth,      ///< P6.0: right pan-tilt depth camera, one rotation (5 s)
  kEvaluateRightDepth,  ///< P6.1
  kScanLeftDepth,       ///< P7.0: left pan-tilt depth camera
  kEvaluateLeftDepth,   ///< P7.1
  kExtractMarker,       ///< P8.0: the marker's ID, class and coordinates
  kCheckPalletId,       ///< P8.1: is it a pallet sought?
  kCheckRackId,         ///< P8.2: is it a rack sought?
  kCheckBoxId,          ///< P8.3: is it a box sought?
  kPublishMarker,       ///< P8.4: the marker goes to the caller
  kReportNoMarker,      ///< P9.0: the caller is told that no marker was found
};

/// The net's scan counter (cntr = 1 after the first, quick scan; cntr > 1 after the step-mode
/// rescan) and the camera in use are token conditions; here they are explicit events.
enum class PickerLocalizationEvent {
  kReady,                    ///< T1
  kScanBothRgbRequested,     ///< T2
  kScanRearRgbRequested,     ///< T3
  kScanFrontRgbRequested,    ///< T4
  kScanLeftDepthRequested,   ///< T5
  kScanRightDepthRequested,  ///< T9
  kScanDone,                 ///< T7, T10, T14, T18, T19
  kMarkerSeen,               ///< T11, T12, T13, T21, T26
  kQuickScanMissed,          ///< T6, T15, T16, T17, T20: none seen, cntr = 1: rescan in step mode
  kStepScanMissed,           ///< T8, T22, T35, T36, T37: none seen, cntr > 1: report no marker
  kPalletMarkerSeen,         ///< T25: the extracted marker is of the pallet class
  kRackMarkerSeen,           ///< T23
  kBoxMarkerSeen,            ///< T24
  kIdSought,                 ///< T27, T28, T29: the ID is in the caller's list
  kWrongId,                  ///< T33, T34: a rack or pallet ID not in the list: scan again
  kWrongBoxIdLeftCamera,     ///< T30: a box ID not in the list, seen by the left depth camera: rescan with it
  kWrongBoxIdRightCamera,    ///< T32: the same with the right depth camera
  kWrongIdAgain,             ///< added: a wrong ID after the rescan: report no marker
  kPublished,                ///< T31
  kMessageSent,              ///< T38
};

const char* to_string(PickerLocalizationState state);
const char* to_string(PickerLocalizationEvent event);

struct PickerLocalizationTransition {
  PickerLocalizationState from;
  PickerLocalizationEvent event;
  PickerLocalizationState to;
  int seed_transition;  ///< the net's transition number; 0 when added beyond the net
};

/// Every transition of the localization supervisor; anything else is refused.
std::span<const PickerLocalizationTransition> picker_localization_table();
/// The state `event` leads to from `from`, or nothing.
std::optional<PickerLocalizationState> next_picker_localization_state(PickerLocalizationState from,
                                                                      PickerLocalizationEvent event);

}  // namespace fleet::task
