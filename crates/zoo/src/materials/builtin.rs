//! The built-in materials, compiled into the crate: one `materials/<id>.toml` file each, read
//! with `include_str!` so that nothing is read from disk at run time.

/// `(file, text)` of a built-in material; `file` is the path in the repository.
macro_rules! builtin {
    ($($id:literal),* $(,)?) => {
        [$((
            concat!("materials/", $id, ".toml"),
            include_str!(concat!("../../materials/", $id, ".toml")),
        )),*]
    };
}

/// Every built-in material file, sorted by id.
pub(super) const BUILTIN: [(&str, &str); 47] = builtin![
    "apple",
    "apple-juice",
    "budweiser-beer",
    "cappuccino-powder",
    "chardonnay",
    "chicken1",
    "chicken2",
    "clorox",
    "coke",
    "coors-light-beer",
    "cranberry-juice",
    "cream",
    "espresso",
    "gatorade",
    "grape-juice",
    "head-and-shoulders-shampoo",
    "ketchup",
    "lemon-tea-powder",
    "lowfat-chocolate-milk",
    "lowfat-milk",
    "lowfat-soy-milk",
    "marble",
    "merlot",
    "mint-mocha-coffee",
    "orange-powder",
    "pacific-ocean-surface-water",
    "pepsi",
    "pink-lemonade-powder",
    "potato",
    "reduced-milk",
    "regular-chocolate-milk",
    "regular-milk",
    "regular-soy-milk",
    "ruby-grapefruit-juice",
    "salt-powder",
    "shampoo",
    "skim-milk",
    "skin1",
    "skin2",
    "spectralon",
    "sprite",
    "strawberry-shampoo",
    "sugar-powder",
    "suisse-mocha-powder",
    "white-grapefruit-juice",
    "white-zinfandel",
    "whole-milk",
];
