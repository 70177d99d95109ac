// The text helpers of scene's motion readers (pose lists, G-code) live in core,
// shared with the pipeline's pose files.
#pragma once

#include "core/text_fields.h"
