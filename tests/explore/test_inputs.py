

def test_a_list_of_loads_typed_with_commas_is_the_study_list():
    """A pinned design with a list of loads fills the field as "0.5N, 1N, 2N": that text is read
    back as the study's list (it was one unreadable quantity)."""
    from fingerpad.explore.inputs import study_data, validate

    data = study_data({"texture.name": "caps", "texture.radius": "100um", "texture.height": "20um",
                       "texture.spacing": "175um", "loads.range": "0.5N, 1N, 2N", "model.kind": "hertz"})
    assert data["loads"]["range"] == ["0.5N", "1N", "2N"]
    check = validate(data)
    assert not check.errors, check.errors
    assert list(check.study.loads) == [0.5, 1.0, 2.0]
