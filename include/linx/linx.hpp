// Umbrella header: the whole public API.
#pragma once

#include <linx/actuator.hpp>
#include <linx/body.hpp>
#include <linx/checkpoint.hpp>
#include <linx/contact.hpp>
#include <linx/import.hpp>
#include <linx/integrator.hpp>
#include <linx/joint.hpp>
#include <linx/joint_defs.hpp>
#include <linx/loads.hpp>
#include <linx/mass_properties.hpp>
#include <linx/recorder.hpp>
#include <linx/row.hpp>
#include <linx/scene.hpp>
#include <linx/shape.hpp>
#include <linx/signal.hpp>
#include <linx/solver.hpp>
#include <linx/types.hpp>
#include <linx/world.hpp>
