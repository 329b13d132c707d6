"""Target sets drawn from a scene's vessel tree."""


def branch_targets(model, lead, min_branchings=3, max_branchings=6,
                   avoid=("brachiocephalic_trunk",)):
    """The vessels ``min_branchings``..``max_branchings`` bifurcations (a
    branch entered from its parent) from the one where the lead device's
    tip starts, wider than 1.5 times its tip's
    radius, whose path does not pass ``avoid`` (the 45° catheter of
    ``network_navigation`` does not engage the brachiocephalic trunk), as
    the network benchmark of ``evsim bench navigation`` draws them."""
    import endovascular_sim as evs

    data = evs.make_data(model)
    entry = data.tips[lead]["vessel"]
    tip_radius = model.devices[lead]["radius"]
    parent = {name: model.vessel(name)["parent"] for name in model.vessel_names}
    found = []
    for name in model.vessel_names:
        path = model.vessel_path(entry, name)
        branchings = sum(parent[b] == a for a, b in zip(path, path[1:]))
        if not (min_branchings <= branchings <= max_branchings):
            continue
        if model.vessel(name)["radius"] <= 1.5 * tip_radius or any(a in path for a in avoid):
            continue
        found.append(name)
    return found
