"""skelgrasp: skeleton-based grasp planning for multi-fingered robot hands.

numpy in and out, no file round-trips (docs/python.md)::

    import skelgrasp
    mesh = skelgrasp.load_mesh("mug.ply")            # or skelgrasp.Mesh(vertices, faces)
    result = skelgrasp.plan(mesh, skelgrasp.hand("sdh"), seed=1)  # or options: PlanOptions()
    best = result.grasps[0]
    best.hand_pose, best.epsilon, best.joints

Errors raise ValueError (bad arguments or data), FileNotFoundError / OSError (files) with the
message the command line prints.
"""
from ._skelgrasp import (  # noqa: F401
    CloseResult,
    ClosingParams,
    Grasp,
    Hand,
    Mesh,
    PlanOptions,
    PlanResult,
    PointCloud,
    QualityParams,
    Reconstruction,
    RobustnessParams,
    RobustRankingParams,
    RobustRefinementParams,
    RunResult,
    SceneObject,
    SceneRunResult,
    Skeleton,
    SkeletonParams,
    SkeletonPlannerParams,
    SurfacePlannerParams,
    close,
    hand,
    hands,
    load_cloud,
    load_hand,
    load_mesh,
    plan,
    reconstruct,
    render_grasp,
    render_plan,
    run,
    score,
    score_grasps,
    set_log_level,
    simulate,
    skeleton,
)

__all__ = [name for name in dir() if not name.startswith("_")]
