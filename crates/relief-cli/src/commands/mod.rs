//! One module per command family; each command is a function taking its parsed arguments and the
//! [`Ui`](crate::ui::Ui), and printing its own report.

pub(crate) mod analyze;
pub(crate) mod dem;
pub(crate) mod prominence;
pub(crate) mod scenes;
pub(crate) mod serve;
pub(crate) mod shell;
pub(crate) mod vector;
