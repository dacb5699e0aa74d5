#pragma once

// The picker's three supervisors [Picker thesis, section 5.3.3.1, Figs. 5.3, 5.8, 5.13]:
// navigation is the global supervisor and calls the localization and arm machines as services;
// the arm calls localization and asks navigation to move the robot.
#include "task/picker_arm.hpp"
#include "task/picker_localization.hpp"
#include "task/picker_navigation.hpp"
