// A scene's methods ("scene."): load a scene document, start and stop it, and the pointer's
// samples, each rendered by the host library's Scene and sent to the board latest-wins; every
// client is told each finger's target as the scene moves.
#pragma once

#include <string>
#include <vector>

#include "palpa/host/scene_file.h"
#include "palpa/serve/board_methods.h"

namespace palpa::serve {

/// A scene the operator named on the command line (palpa serve --scene FILE): read from the
/// server's disk at start, offered to pages by name. A page itself never names a file.
struct ServerScene {
  std::string name;
  host::SceneSpec spec;
};

/// The scene group for a board that said `board` at Hello: scene.info, scene.load (a scene
/// document whose tissue is a preset or a phantom, or one of `server_scenes` by name),
/// scene.start, scene.stop, and scene.pointer (a notification: {"x_mm", "y_mm", "force_n"}).
MethodGroup SceneMethods(const protocol::HelloReply& board, std::vector<ServerScene> server_scenes);

}  // namespace palpa::serve
